"""RoadDistance: odometry path length when known, else dead reckoning; unwrapped heading."""
import math

import pytest

from conde_decision.road_distance import RoadDistance, road_direction_rad


def test_dead_reckons_without_odometry_path_length():
    road = RoadDistance()
    assert road.advance(0.2) == 0.2 and road.advance(0.3) == 0.3
    assert road.travelled_m == pytest.approx(0.5)
    road.on_odometry(1.0)  # heading only
    assert road.advance(0.1) == 0.1


def test_odometry_path_length_replaces_dead_reckoning_from_its_first_value():
    road = RoadDistance()
    road.on_odometry(0.0, 5.0)  # the first value is the reference, not a step
    assert road.advance(0.4) == 0.0
    road.on_odometry(0.0, 5.25)
    assert road.advance(0.4) == pytest.approx(0.25)
    road.on_odometry(0.0, 5.2)  # odometry never drives backwards along the road
    assert road.advance(0.4) == 0.0
    road.on_odometry(0.0, float("nan"))
    assert road.advance(0.4) == 0.0
    assert road.travelled_m == pytest.approx(0.25)


def test_heading_is_unwrapped():
    road = RoadDistance()
    assert road.yaw_rad is None
    for yaw in (3.0, -3.0, -1.0, 1.0, 3.1, float("inf")):
        road.on_odometry(yaw)
    assert road.yaw_rad == pytest.approx(3.1 + 2.0 * math.pi)


def test_the_road_direction_is_the_heading_less_the_heading_error():
    assert road_direction_rad(1.0, 0.2) == pytest.approx(0.8)
    assert road_direction_rad(7.0, -0.5) == pytest.approx(7.5)  # the unwrapped heading's branch is kept


@pytest.mark.parametrize("yaw_rad, heading_error_rad", [(None, 0.1), (float("nan"), 0.1), (1.0, float("nan")),
                                                        (1.0, float("inf"))])
def test_no_road_direction_without_a_heading_or_a_heading_error(yaw_rad, heading_error_rad):
    assert road_direction_rad(yaw_rad, heading_error_rad) is None
