"""conde_tracking.parking_area on views rendered by the simulator in the B2 worlds (box in the north
bay: b2v1_*, in the south bay: b2v2_*), against the track geometry (conde_tracking.bay_truth), and
on ground points drawn to known measures."""
import functools
import math
import os

import numpy as np
import pytest

from conde_tracking.bay_truth import lines_in_robot_frame, load_views, occupied_bay
from conde_tracking.ipm import GroundMap
from conde_tracking.obstacles import ObstacleDetector
from conde_tracking.parking_area import BayLine, ParkingAreaConfig, ParkingAreaDetector, bays_between

DATA = os.path.join(os.path.dirname(os.path.abspath(__file__)), "data")
VIEWS = dict(load_views(DATA))
SEEN_X_M = (0.4, 1.5)  # a border line this far ahead is in full view


@functools.lru_cache(maxsize=None)
def detect(name):
    d = VIEWS[name]
    maps = [GroundMap.from_camera(160, 120, d[f"{k}_K"], d[f"{k}_D"], d[f"{k}_T_base_optical"])
            for k in ("left", "right")]
    images = [d["left_image"], d["right_image"]]
    return ParkingAreaDetector(maps).detect(images), ObstacleDetector(maps).detect(images), d


@pytest.mark.parametrize("name", sorted(VIEWS))
def test_the_border_lines_in_view_are_found_within_4_cm(name):
    lines, _, d = detect(name)
    truth = lines_in_robot_frame(d["pose_xy_yaw"])
    for which in ("south_border", "north_border"):
        hidden = which == "north_border" and occupied_bay(name) == "north"  # behind the box
        if SEEN_X_M[0] <= truth[which] <= SEEN_X_M[1] and not hidden:
            assert min(abs(line.x_m - truth[which]) for line in lines) <= 0.04, (which, truth, lines)


@pytest.mark.parametrize("name", [n for n in sorted(VIEWS) if "heading" not in n])
def test_heading_along_the_road_every_line_found_is_a_bay_line(name):
    lines, _, d = detect(name)
    truth = list(lines_in_robot_frame(d["pose_xy_yaw"]).values())
    for line in lines:
        assert min(abs(line.x_m - t) for t in truth) <= 0.04, (line, truth)
        assert abs(line.angle_rad) <= math.radians(4)


def test_the_bay_between_two_lines_seen_is_free_or_holds_the_box():
    lines, boxes, d = detect("b2v1_bays_ahead_0_5m")  # south border and divider in view, box in the north bay
    truth = lines_in_robot_frame(d["pose_xy_yaw"])
    (bay,) = bays_between(lines, boxes)
    assert bay.near_x_m == pytest.approx(truth["south_border"], abs=0.04) and not bay.occupied
    assert bay.far_x_m == pytest.approx(truth["divider"], abs=0.04)
    assert occupied_bay("b2v1_bays_ahead_0_5m") == "north"
    # the same bay with a box seen between its lines, off the road
    box = type(boxes[0])("box", 0.7, -1.4, -0.95, 100)
    assert [b.occupied for b in bays_between(lines, [box])] == [True]
    on_road = type(boxes[0])("box", 0.7, -0.3, 0.1, 100)
    assert [b.occupied for b in bays_between(lines, [on_road])] == [False]


def line_points(x_m, y_from_m, y_to_m, step_m=0.02, width_m=0.05, dash=None):
    """Ground points of a painted line across the road at x_m from y_from_m to y_to_m (y_from_m >
    y_to_m), dashed (dash, gap) [m] if given."""
    ys = np.arange(y_to_m, y_from_m, step_m)
    if dash is not None:
        ys = ys[np.mod(y_from_m - ys, sum(dash)) < dash[0]]
    xs = np.arange(x_m - width_m / 2, x_m + width_m / 2, step_m)
    gx, gy = np.meshgrid(xs, ys)
    return np.column_stack([gx.ravel(), gy.ravel()])


def border_along_road(y_m, x_from_m=0.3, x_to_m=1.8):
    xs = np.arange(x_from_m, x_to_m, 0.02)
    return np.column_stack([xs, np.full(len(xs), y_m)])


def test_drawn_lines_a_solid_and_a_dashed_one_are_found_the_letter_p_off_the_border_is_not():
    detector = ParkingAreaDetector([])
    pts = np.concatenate([
        border_along_road(-0.75), border_along_road(-0.76),  # the bays' border along the road
        line_points(0.6, -0.73, -1.75),  # a border across the road
        line_points(1.0, -0.73, -1.65, dash=(0.2, 0.15)),  # the dashed divider
        line_points(1.3, -0.99, -1.49),  # a "P" stem, 0.19 m off the border
        border_along_road(-1.72), border_along_road(-1.73)])  # the far border along the road
    lines = detector.lines_in(pts)
    assert [line.x_m for line in lines] == [pytest.approx(0.6, abs=0.02), pytest.approx(1.0, abs=0.02)]
    assert all(isinstance(line, BayLine) and line.length_m >= 0.7 for line in lines)


def test_a_tilted_line_is_found_at_its_road_end():
    detector = ParkingAreaDetector([])
    angle = math.radians(6)
    ys = np.arange(-1.7, -0.7, 0.01)
    pts = np.column_stack([1.0 - (ys + 0.7) * math.tan(angle), ys])
    pts = np.concatenate([pts, pts + [0.02, 0.0], pts - [0.02, 0.0]])
    (line,) = detector.lines_in(pts)
    assert line.x_m == pytest.approx(1.0, abs=0.02) and line.angle_rad == pytest.approx(angle, abs=0.04)


def test_bad_config_names_the_field():
    with pytest.raises(ValueError, match="^band_y_m: expected"):
        ParkingAreaConfig(band_y_m=(-0.5, -2.0)).check()
    with pytest.raises(ValueError, match="^min_length_m: must be > 0"):
        ParkingAreaConfig(min_length_m=0.0).check()
