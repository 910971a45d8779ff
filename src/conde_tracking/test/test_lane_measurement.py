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


def brute_force_search(lm, pts):
    """The coarse search by its definition: every grid model against every point."""
    c = lm.config
    if len(pts) > c.search_points:
        pts = pts[np.linspace(0, len(pts) - 1, c.search_points).astype(int)]
    c0s, shapes = lm._grid_axes
    grid = np.array([(c0, c1, c2) for c0 in c0s for c1, c2 in shapes])
    x, y = pts[:, 0][None, :], pts[:, 1][None, :]
    d = y - (grid[:, 0:1] + grid[:, 1:2] * x + grid[:, 2:3] * x * x)
    k = np.sqrt(1.0 + (grid[:, 1:2] + 2 * grid[:, 2:3] * x) ** 2)
    score = sum((np.abs(d - off * k) < c.line_window_m).sum(1) for off in (c.right_line_offset_m, c.left_line_offset_m))
    return grid[int(np.argmax(score))]


def test_the_coarse_search_finds_the_model_its_definition_finds():
    _, lm, _ = load("centred")
    rng = np.random.default_rng(7)
    point_sets = []
    for name in POSES:
        d, lm_pose, images = load(name)
        point_sets.append(lm_pose.ground_white(images)[0])
    for _ in range(40):  # two noisy lines of a random lane, and clutter
        c0, c1, c2 = rng.uniform(-0.3, 0.3), rng.uniform(-0.6, 0.6), rng.uniform(-0.6, 0.6)
        x = rng.uniform(0.0, 1.3, 400)
        off = np.where(rng.random(400) < 0.5, lm.config.right_line_offset_m, lm.config.left_line_offset_m)
        y = c0 + c1 * x + c2 * x * x + off * np.sqrt(1 + (c1 + 2 * c2 * x) ** 2) + rng.normal(0, 0.01, 400)
        clutter = rng.uniform([0.0, -1.3], [1.3, 1.3], (60, 2))
        point_sets.append(np.vstack([np.column_stack([x, y]), clutter]))
    for pts in point_sets:
        np.testing.assert_array_equal(lm._coarse_search(pts), brute_force_search(lm, pts))
