"""Lap timing and lane keeping of the autonomous-run evaluation, on paths built from the track
geometry itself."""
import math

import numpy as np
import pytest

from conde_eval import run_evaluation
from conde_worlds import track_geometry as tg


@pytest.fixture(scope="module")
def lane():
    centres = tg.build_track().lane_centres(spacing=0.05)["north_ccw"]
    return centres["xy"]


def drive(timer, xy, speed_mps=0.5, t0_s=0.0):
    t = t0_s
    timer.feed(t, xy[0][0], xy[0][1])
    for a, b in zip(xy, xy[1:]):
        t += math.hypot(*(b - a)) / speed_mps
        timer.feed(t, b[0], b[1])
    return t


def test_two_laps_of_the_lane_centre_are_two_laps_of_the_route_length(lane):
    start = np.array([[2.169, -0.33]])
    path = np.vstack([start, lane, lane, lane[:10]])  # the route starts at y = 0 going north
    # Laps: from the first motion to the line 0.21 m before the crosswalk, then line to line.
    timer = run_evaluation.LapTimer()
    drive(timer, path)
    route_length_m = tg.build_track().lane_centres()["north_ccw"]["length"]
    assert len(timer.laps_s) == 2
    for lap in timer.laps_s:
        assert lap == pytest.approx(route_length_m / 0.5, rel=0.01)
    assert timer.motion_start_s == 0.0 and len(timer.crossings_s) == 2
    assert timer.top_speed_mps == pytest.approx(0.5, rel=1e-6)


def test_southbound_crossings_are_not_laps(lane):
    timer = run_evaluation.LapTimer()
    drive(timer, np.array([[1.387, 1.0], [1.387, -1.0]]))  # west lane, southbound
    drive(timer, np.array([[1.387, -1.0], [1.387, 1.0]]))  # northbound, but in the west lane
    assert timer.crossings_s == []


def test_the_lane_centre_stays_in_its_lane(lane):
    result = run_evaluation.lane_keeping(lane)
    assert result["stayed_in_lane"]
    assert result["max_offset_m"] < 0.005
    assert result["off_road_points"] == 0


def test_a_path_beside_the_road_leaves_its_lane(lane):
    beside = lane.copy()
    beside[100:120, 0] += 1.5  # a detour off the road
    result = run_evaluation.lane_keeping(beside)
    assert not result["stayed_in_lane"]
    assert result["max_offset_m"] > run_evaluation.LANE_HALF_WIDTH_M
    assert result["in_lane_fraction"] < 1.0


def test_plot_is_written(tmp_path, lane):
    texture = tmp_path / "t.png"
    import matplotlib.pyplot as plt
    plt.imsave(texture, np.zeros((20, 10, 3)))
    out = tmp_path / "path.png"
    run_evaluation.plot_path(lane, str(texture), (-3.475, 3.975, -8.35, 8.35), str(out), "test")
    assert out.stat().st_size > 1000
