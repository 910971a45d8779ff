"""Lane measurement on real images rendered by the simulator at known poses (test/data, made by
scripts/render_test_images; the ground truth in each file comes from conde_worlds.track_geometry)."""
import math
import os

import numpy as np
import pytest

from conde_tracking.ipm import GroundMap
from conde_tracking.lane_measurement import LaneMeasurement, white_mask

DATA = os.path.join(os.path.dirname(os.path.abspath(__file__)), "data")
POSES = ["centred", "left_5cm", "right_5cm", "heading_left_10deg", "heading_right_10deg", "near_crosswalk"]
CROSSWALK_NEAR_EDGE_Y_M = -0.340  # world y of the near (south) edge of the crosswalk's bottom bar


def load(name):
    d = np.load(os.path.join(DATA, name + ".npz"))
    maps = [GroundMap.from_camera(160, 120, d[f"{k}_K"], d[f"{k}_D"], d[f"{k}_T_base_optical"])
            for k in ("left", "right")]
    return d, LaneMeasurement(maps), [d["left_image"], d["right_image"]]


@pytest.mark.parametrize("name", POSES)
def test_offset_and_heading_match_ground_truth(name):
    d, lm, images = load(name)
    r = lm.measure(images)
    assert r.confidence == 1.0
    assert abs(r.lateral_offset_m - float(d["lateral_offset_m"])) < 0.02
    assert abs(math.degrees(r.heading_error_rad - float(d["heading_error_rad"]))) < 3.0
    # tighter: what the rendered images actually give (regression guard)
    assert abs(r.lateral_offset_m - float(d["lateral_offset_m"])) < 0.005


@pytest.mark.parametrize("name", ["left_5cm", "heading_right_10deg"])
def test_a_fit_from_the_previous_result_gives_the_same_measurement(name):
    d, lm, images = load(name)
    first = lm.measure(images)
    again = lm.measure(images, prior=first.fit.coeffs)
    assert again.lateral_offset_m == pytest.approx(first.lateral_offset_m, abs=1e-3)
    assert again.heading_error_rad == pytest.approx(first.heading_error_rad, abs=math.radians(0.2))


def test_crosswalk_ahead_and_its_distance():
    d, lm, images = load("near_crosswalk")
    r = lm.measure(images)
    assert r.crosswalk_seen
    expected = CROSSWALK_NEAR_EDGE_Y_M - float(d["pose_xy_yaw"][1])  # robot heads north
    assert abs(r.crosswalk_distance_m - expected) < 0.02


@pytest.mark.parametrize("name", ["centred", "left_5cm", "heading_left_10deg"])
def test_no_crosswalk_far_from_it(name):
    _, lm, images = load(name)
    assert not lm.measure(images).crosswalk_seen


def test_one_camera_black_gives_one_line_and_half_confidence():
    d, lm, images = load("right_5cm")
    r = lm.measure([np.zeros_like(images[0]), images[1]])  # left camera sees nothing white
    assert r.confidence == 0.5
    assert abs(r.lateral_offset_m - float(d["lateral_offset_m"])) < 0.02


def test_black_images_give_no_lane():
    _, lm, images = load("centred")
    r = lm.measure([np.zeros_like(images[0]), np.zeros_like(images[1])])
    assert r.confidence == 0.0 and not r.crosswalk_seen and r.fit is None


def test_white_mask_needs_every_channel_bright():
    img = np.array([[[255, 255, 255], [170, 200, 230], [255, 255, 0]]], dtype=np.uint8)
    assert white_mask(img, 140).tolist() == [[True, True, False]]
    assert white_mask(np.array([[100, 200]], np.uint8), 140).tolist() == [[False, True]]
