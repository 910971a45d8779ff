"""Boxes and cones found by conde_tracking.obstacles in views the simulator rendered in the D4 v1
world (test/data/d4_*.npz, scripts/render_test_images), against the challenge layout's ground truth
(conde_worlds)."""
import os

import numpy as np
import pytest

from conde_tracking.ipm import GroundMap
from conde_tracking.obstacles import BOX, CONE, ObstacleConfig, ObstacleDetector, colour_masks
from conde_tracking.obstacle_truth import VIEWS, objects_in_robot_frame

DATA = os.path.join(os.path.dirname(os.path.abspath(__file__)), "data")
CONFIG = ObstacleConfig()
#: An object whose near edge is in this x range [m] and reaches within LATERAL_M of the robot's
#: axis must be found (both cameras see the floor there).
MUST_SEE_X_M = (0.3, 1.5)
LATERAL_M = 0.8
VIEW_MIN_X_M = -0.15  # the cameras see the floor from about x = -0.2 m: nearer edges are out of view


def load(name):
    d = np.load(os.path.join(DATA, name + ".npz"))
    maps = [GroundMap.from_camera(160, 120, d[f"{k}_K"], d[f"{k}_D"], d[f"{k}_T_base_optical"])
            for k in ("left", "right")]
    return d, ObstacleDetector(maps, CONFIG), [d["left_image"], d["right_image"]]


def match(detection, truths):
    """The true object of the detection's kind nearest to its near-edge point."""
    same = [t for t in truths if t.kind == detection.kind]
    point = np.array([detection.near_x_m, detection.y_centre_m])
    return min(same, key=lambda t: np.min(np.hypot(*(t.footprint_xy_m - point).T)))


@pytest.mark.parametrize("name", VIEWS)
def test_every_detection_is_a_real_object_where_it_is(name):
    d, det, images = load(name)
    truths = objects_in_robot_frame(d["pose_xy_yaw"])
    found = det.detect(images)
    assert found, "nothing found"
    for f in found:
        t = match(f, truths)
        if t.near_x_m > VIEW_MIN_X_M:
            assert abs(f.near_x_m - t.near_x_m) < 0.1, (f, t.name, t.near_x_m)
        # the lateral extent seen lies on the object (a part of it may be out of view)
        assert t.y_min_m - 0.1 <= f.y_min_m and f.y_max_m <= t.y_max_m + 0.1, (f, t.name, t.y_min_m, t.y_max_m)


@pytest.mark.parametrize("name", VIEWS)
def test_every_object_in_view_is_found(name):
    d, det, images = load(name)
    truths = objects_in_robot_frame(d["pose_xy_yaw"])
    found = det.detect(images)
    for t in truths:
        if MUST_SEE_X_M[0] <= t.near_x_m <= MUST_SEE_X_M[1] and t.y_min_m < LATERAL_M and t.y_max_m > -LATERAL_M:
            assert any(f.kind == t.kind and match(f, truths) is t for f in found), (t.name, t.near_x_m, found)


def test_the_box_ahead_is_one_box_in_the_lane():
    _, det, images = load("d4_box_ahead_1m")
    found = det.detect(images)
    assert [f.kind for f in found] == [BOX]
    assert found[0].y_min_m < 0.0 < found[0].y_max_m


def test_lane_lines_and_the_grey_floor_are_not_obstacles():
    _, det, images = load("centred")  # the competition track without objects
    assert det.detect(images) == []


def test_darker_light_classifies_the_same():
    _, det, images = load("d4_cones_ahead")
    bright = det.detect(images)
    dark = det.detect([(img.astype(float) * 0.35).astype(np.uint8) for img in images])
    assert [f.kind for f in dark] == [f.kind for f in bright]
    for a, b in zip(dark, bright):
        assert abs(a.near_x_m - b.near_x_m) < 0.05


def test_colour_masks_of_pure_colours():
    img = np.array([[[0, 200, 0], [230, 62, 0], [255, 255, 255], [90, 90, 90]]], dtype=np.uint8)
    green, orange = colour_masks(img, CONFIG)
    assert green.tolist() == [[True, False, False, False]]
    assert orange.tolist() == [[False, True, False, False]]
    assert CONE != BOX


def test_bad_config_names_the_field():
    with pytest.raises(ValueError, match="max_range_m"):
        ObstacleConfig(max_range_m=0).check()
