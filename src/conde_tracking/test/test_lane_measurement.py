"""Lane measurement on real images rendered by the simulator at known poses (test/data, made by
scripts/render_test_images; the ground truth in each file comes from conde_worlds.track_geometry)."""
import math
import os
from dataclasses import replace

import numpy as np
import pytest

from conde_tracking.ipm import GroundMap
from conde_tracking.lane_measurement import (DASHED, LEFT_LANE, RIGHT_LANE, SOLID, UNKNOWN_LANE, LaneMeasurement,
                                             LaneResult, _darkest_channel, line_mask, white_mask)

import synthetic_views

DATA = os.path.join(os.path.dirname(os.path.abspath(__file__)), "data")
POSES = ["centred", "left_5cm", "right_5cm", "heading_left_10deg", "heading_right_10deg", "near_crosswalk"]
JUNCTION_POSES = ["merge_right_corner_ahead", "fork_right_corner_ahead", "fork_left_corner_ahead"]
CORNER_AHEAD_M = {"merge_right_corner_ahead": 0.5, "fork_right_corner_ahead": 0.5, "fork_left_corner_ahead": 0.6}
EDGE_CORNER_RADIUS_M = 1.0 - 0.8065  # the edge line's corner: fork radius less the line's distance from the road centre
CROSSWALK_NEAR_EDGE_Y_M = -0.340  # world y of the near (south) edge of the crosswalk's bottom bar


def load(name):
    d = np.load(os.path.join(DATA, name + ".npz"))
    maps = [GroundMap.from_camera(160, 120, d[f"{k}_K"], d[f"{k}_D"], d[f"{k}_T_base_optical"])
            for k in ("left", "right")]
    return d, LaneMeasurement(maps), [d["left_image"], d["right_image"]]


@pytest.mark.parametrize("name", POSES + JUNCTION_POSES)
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
        np.testing.assert_array_equal(lm._coarse_candidates(pts, 1)[0], brute_force_search(lm, pts))


def assert_fresh_fit_is_the_lane(name, offset_tolerance_m):
    """The fit without prior of a recorded view: both lines, offset and heading (2 deg) as measured."""
    d, lm, images = load(name)
    r = lm.measure(images)
    assert r.confidence == 1.0
    assert abs(r.lateral_offset_m - float(d["lateral_offset_m"])) < offset_tolerance_m
    assert abs(math.degrees(r.heading_error_rad - float(d["heading_error_rad"]))) < 2.0
    return d, lm, images, r


def test_standing_at_the_crosswalk_the_fresh_fit_is_the_lane_not_a_slant_across_the_stripes():
    """track1_place2_start: the simulator's images at 0.067 s of D1 on track seed 1, placement seed 2
    (the robot at the crosswalk's near edge, 2 cm behind the nominal start; K, D and the cameras'
    poses are Conde's, as in the other views).  The grid's best model on its 300 subsampled points
    was one 40 deg to the right across the stripes (offset -0.22 m, heading -0.67 rad); the
    following fits started from it kept it and the robot turned left 90 deg after the go."""
    assert_fresh_fit_is_the_lane("track1_place2_start", 0.01)


def test_at_the_p1_start_on_track_4_placement_4_the_fresh_fit_is_the_lane():
    """track4_place4_start: the simulator's images at 0.1 s of P1 on track seed 4, placement seed 4
    (4.9 cm left of the lane centre, 2.8 deg left, 5 cm before the crosswalk's near edge), where
    the robot once turned left off the start.  The robot still settling, this view is fitted right
    also with 300 search points; the tracker's first frame (below) was not."""
    assert_fresh_fit_is_the_lane("track4_place4_start", 0.01)


def test_the_first_frame_at_the_p1_start_on_track_4_is_fitted_to_the_lane_not_the_crosswalk():
    """track4_place4_first_frame: the images at 0.233 s of the same start (the tracker's first frame
    in the lock-step run, the robot settled).  The coarse search on 300 of its 6127 points (most of
    them the crosswalk's) kept a model 22 deg off; every later frame started from the one before and
    the fit crept to 55 deg off before the go; the lane follower then turned the robot left off the
    start.  With 1500 points the search's best is the lane, and fits from it stay on it."""
    d, lm, images, r = assert_fresh_fit_is_the_lane("track4_place4_first_frame", 0.02)
    for _ in range(30):  # the robot stands: each frame starts from the last one's fit
        r = lm.measure(images, prior=lm.next_prior(r))
    assert abs(r.lateral_offset_m - float(d["lateral_offset_m"])) < 0.02
    assert abs(math.degrees(r.heading_error_rad - float(d["heading_error_rad"]))) < 2.0
    old = LaneMeasurement(lm.ground_maps, replace(lm.config, search_points=300)).measure(images)
    assert abs(math.degrees(old.heading_error_rad - float(d["heading_error_rad"]))) > 20.0


def test_the_search_candidates_are_unlike_and_the_best_comes_first():
    d, lm, images = load("track1_place2_start")
    pts = lm.ground_white(images)[0]
    c = lm.config
    pts = pts[(pts[:, 0] <= c.fit_range_m[1]) & (np.abs(pts[:, 1]) <= c.max_abs_y_m)]
    candidates = lm._coarse_candidates(pts, 4)
    assert len(candidates) == 4
    np.testing.assert_array_equal(candidates[0], lm._coarse_candidates(pts, 1)[0])
    for i, a in enumerate(candidates):
        for b in candidates[:i]:
            assert abs(a[0] - b[0]) >= 2 * c.line_window_m or abs(math.atan(a[1]) - math.atan(b[1])) >= math.radians(6)
    # with one candidate (the search's best alone, on 300 points) this view is measured 40 deg off
    one = LaneMeasurement(lm.ground_maps, replace(c, search_candidates=1, search_points=300)).measure(images)
    assert abs(math.degrees(one.heading_error_rad - float(d["heading_error_rad"]))) > 20.0


# --- any light, any drawing within the rules ----------------------------------------------------

def dimmed(images, light, rng, noise=3.0):
    """The images under a light level (0..1), with grey-level noise (standard deviation [0..255])."""
    return [np.clip(img * light + rng.normal(0.0, noise, img.shape), 0, 255).astype(np.uint8) for img in images]


@pytest.mark.parametrize("light", [0.5, 0.35, 0.25])
@pytest.mark.parametrize("name", ["centred", "left_5cm", "heading_right_10deg", "near_crosswalk"])
def test_the_lane_and_crosswalk_in_the_tunnels_darker_light(name, light):
    """The D4 tunnel dims the light to 0.35: its white lines (89 of 255) are below white_threshold."""
    d, lm, images = load(name)
    r = lm.measure(dimmed(images, light, np.random.default_rng(3)))
    assert r.confidence == 1.0
    assert abs(r.lateral_offset_m - float(d["lateral_offset_m"])) < 0.005
    assert abs(math.degrees(r.heading_error_rad - float(d["heading_error_rad"]))) < 1.0
    assert r.crosswalk_seen == (name == "near_crosswalk")


def test_the_lane_inside_the_d4_tunnel():
    """Rendered by the simulator in the D4 world (render_test_images d4_in_tunnel): the lines at 89
    of 255 under the tunnel's light, grey walls; the fixed threshold alone sees one line (the left
    camera's view leaves the tunnel), the line mask both."""
    d, lm, images = load("d4_in_tunnel")
    r = lm.measure(images)
    assert r.confidence == 1.0
    assert abs(r.lateral_offset_m - float(d["lateral_offset_m"])) < 0.005
    assert abs(math.degrees(r.heading_error_rad - float(d["heading_error_rad"]))) < 1.5
    assert not white_mask(images[1], lm.config.white_threshold).any()
    fixed_threshold_only = LaneMeasurement(lm.ground_maps, replace(lm.config, min_contrast=256))
    assert fixed_threshold_only.measure(images).confidence < 1.0


def test_the_lane_across_a_light_boundary():
    """Entering the tunnel: the far part of the view dark, the near part lit."""
    d, lm, images = load("left_5cm")
    dark = dimmed(images, 0.35, np.random.default_rng(4))
    mixed = [np.concatenate([dk[:70], img[70:]]) for dk, img in zip(dark, images)]
    r = lm.measure(mixed)
    assert r.confidence == 1.0
    assert abs(r.lateral_offset_m - float(d["lateral_offset_m"])) < 0.005


def test_grey_noise_in_the_dark_is_no_line():
    _, lm, images = load("centred")
    rng = np.random.default_rng(5)
    noise = [np.clip(rng.normal(30.0, 8.0, img.shape), 0, 255).astype(np.uint8) for img in images]
    assert not line_mask(noise[0], lm.config).any()
    assert lm.measure(noise).confidence == 0.0


def test_line_mask_keeps_every_white_pixel():
    _, lm, images = load("near_crosswalk")
    for img in images:
        white = white_mask(img, lm.config.white_threshold)
        assert white.any() and np.all(line_mask(img, lm.config)[white])


def synthetic_setup():
    d, _, _ = load("centred")
    cams = [(d[f"{k}_K"], d[f"{k}_D"], d[f"{k}_T_base_optical"]) for k in ("left", "right")]
    fine = [synthetic_views.supersampled_map(160, 120, *cam) for cam in cams]
    return fine, [GroundMap.from_camera(160, 120, *cam) for cam in cams]


VIEWS = [(0.0, 0.0), (0.05, 0.0), (-0.05, 0.0), (0.0, math.radians(10)), (0.03, math.radians(-8))]


@pytest.mark.parametrize("lane_width_m", [0.709, 0.746, 0.783])  # nominal +- 5 %
@pytest.mark.parametrize("right_width_m, left_width_m",
                         [(0.05, 0.05), (0.10, 0.10), (0.085, 0.036), (0.05, 0.10), (0.10, 0.05)])
def test_lanes_drawn_within_the_rules(lane_width_m, right_width_m, left_width_m):
    """Line widths 5 to 10 cm, lane width +-5 %: the measured lane centre is the one between the
    lines' inner edges within 3 cm (the lines' widths are not measured: the configured midpoint
    between them is off by a quarter of the difference of the widths from the nominal), heading
    within 3 deg."""
    fine, maps = synthetic_setup()
    lane = synthetic_views.StraightLane(lane_width_m=lane_width_m, right_width_m=right_width_m,
                                        left_width_m=left_width_m)
    for offset_m, heading_rad in VIEWS:
        r = LaneMeasurement(maps).measure([synthetic_views.render(f, lane, offset_m, heading_rad) for f in fine])
        assert r.confidence == 1.0
        assert abs(r.lateral_offset_m - offset_m) < 0.03
        assert abs(math.degrees(r.heading_error_rad - heading_rad)) < 3.0


def test_the_line_separation_is_learnt_and_serves_when_one_line_is_seen():
    """A lane 5 % wider: after frames showing both lines, a frame with the centre line out of
    sight (the left camera black) is measured from the edge line and the learnt separation."""
    fine, maps = synthetic_setup()
    lane = synthetic_views.StraightLane(lane_width_m=0.783)
    true_separation_m = 0.783 + (0.085 + 0.036) / 2
    both = [synthetic_views.render(f, lane, 0.02, 0.0) for f in fine]
    one_line = [np.zeros_like(both[0]), both[1]]
    fresh = LaneMeasurement(maps)
    nominal_error_m = abs(fresh.measure(one_line).lateral_offset_m - 0.02)
    assert nominal_error_m > 0.015  # half the separation's change: why it is learnt
    lm = LaneMeasurement(maps)
    for _ in range(20):
        lm.measure(both)
    assert lm.line_separation_m == pytest.approx(true_separation_m, abs=0.01)
    r = lm.measure(one_line)
    assert r.confidence == 0.5
    assert abs(r.lateral_offset_m - 0.02) < 0.006


def test_the_line_separation_stays_within_its_limits():
    fine, maps = synthetic_setup()
    lane = synthetic_views.StraightLane(lane_width_m=0.746 * 1.4)  # far outside the rules
    lm = LaneMeasurement(maps)
    for _ in range(20):
        lm.measure([synthetic_views.render(f, lane, 0.0, 0.0) for f in fine])
    limit_m = lm.configured_separation_m * (1 + lm.config.max_separation_change)
    assert lm.line_separation_m <= limit_m + 1e-9


# --- junctions ------------------------------------------------------------------------------------

@pytest.mark.parametrize("name", ["merge_right_corner_ahead", "fork_right_corner_ahead"])
def test_the_edge_line_turning_away_at_a_right_turns_corner(name):
    """The right turn's arc begins at the corner (CORNER_AHEAD_M); the edge line leaves its band
    about the corner's radius later."""
    _, lm, images = load(name)
    r = lm.measure(images)
    expected_m = CORNER_AHEAD_M[name] + EDGE_CORNER_RADIUS_M
    assert r.right_line_end_m == pytest.approx(expected_m, abs=0.03)


def test_the_centre_line_ending_before_the_left_branch():
    _, lm, images = load("fork_left_corner_ahead")
    r = lm.measure(images)
    assert math.isnan(r.right_line_end_m)  # the edge line on the right runs on past the fork
    assert CORNER_AHEAD_M["fork_left_corner_ahead"] - 0.2 < r.left_line_end_m < CORNER_AHEAD_M["fork_left_corner_ahead"]


def test_the_far_line_turning_left_at_a_left_turns_corner():
    """The other lane's outer edge line turns left at the corner where the left turn's arc begins
    (CORNER_AHEAD_M), with the same corner radius as the edge line at a right turn."""
    _, lm, images = load("fork_left_corner_ahead")
    r = lm.measure(images)
    assert r.far_left_line_end_m == pytest.approx(CORNER_AHEAD_M["fork_left_corner_ahead"] + EDGE_CORNER_RADIUS_M,
                                                  abs=0.03)


@pytest.mark.parametrize("name", POSES)
def test_no_line_ends_on_the_straight(name):
    """The dashed line's gaps (0.148 m) are no end; lines running beyond the view have none."""
    _, lm, images = load(name)
    r = lm.measure(images)
    assert math.isnan(r.right_line_end_m) and math.isnan(r.left_line_end_m)
    assert math.isnan(r.far_left_line_end_m)  # the other lane's edge line is in view and runs on


class EdgeLineBesideABay(synthetic_views.StraightLane):
    """A junction's gap in the centre line, beside a parking bay: a thin edge line and, 0.3 m to
    its right, the bay's wider border."""

    def paint(self, along_m, left_m):
        edge = -self.lane_width_m / 2
        right = (left_m <= edge) & (left_m >= edge - self.right_width_m)
        bay = (left_m <= edge - 0.30) & (left_m >= edge - 0.39)
        return np.where(right | bay, self.white, self.black)


def test_the_line_followed_before_is_kept_when_a_stronger_one_is_beside_it():
    fine, maps = synthetic_setup()
    lm = LaneMeasurement(maps)
    both = lm.measure([synthetic_views.render(f, synthetic_views.StraightLane(right_width_m=0.055), 0.02, 0.0)
                       for f in fine])
    gap = [synthetic_views.render(f, EdgeLineBesideABay(right_width_m=0.055), 0.02, 0.0) for f in fine]
    assert abs(lm.measure(gap).lateral_offset_m - 0.02) > 0.2  # afresh: the bay's border taken for the edge line
    prior = lm.next_prior(both)
    for _ in range(5):
        r = lm.measure(gap, prior)
        assert r.confidence == 0.5 and abs(r.lateral_offset_m - 0.02) < 0.02
        prior = lm.next_prior(r)


def test_a_prior_whose_lines_are_gone_falls_back_to_a_fresh_search():
    d, lm, images = load("centred")
    r = lm.measure(images, prior=np.array([5.0, 0.0, 0.0]))  # bands 5 m to the left: nothing there
    assert r.confidence == 1.0 and abs(r.lateral_offset_m - float(d["lateral_offset_m"])) < 0.005
    assert lm.next_prior(LaneResult()) is None


# --- which lane ---------------------------------------------------------------------------------

@pytest.mark.parametrize("name", POSES + ["merge_right_corner_ahead", "fork_right_corner_ahead", "d4_in_tunnel",
                                          "d4_box_ahead_1m", "d4_cones_ahead"])
def test_in_the_right_lane_the_edge_line_is_solid_and_the_centre_line_dashed(name):
    _, lm, images = load(name)
    r = lm.measure(images)
    assert (r.right_line_style, r.left_line_style, r.lane_index) == (SOLID, DASHED, RIGHT_LANE)


@pytest.mark.parametrize("name", ["d4_box_beside", "d4_cones_beside"])
def test_in_the_left_lane_of_a_loop_the_dashed_line_is_on_the_right(name):
    """Rendered in the north loop's inner lane, driving the outer lane's way round (passing the box or
    the cones): the ground truth is against the inner lane's own direction (heading 180 deg)."""
    d, lm, images = load(name)
    r = lm.measure(images)
    assert (r.right_line_style, r.left_line_style, r.lane_index) == (DASHED, SOLID, LEFT_LANE)
    assert abs(r.lateral_offset_m + float(d["lateral_offset_m"])) < 0.005
    assert abs(math.degrees(r.heading_error_rad - (float(d["heading_error_rad"]) - math.pi))) < 3.0


def test_the_centre_line_ending_at_a_fork_leaves_the_lane_unknown():
    """Both lines have gaps where the left branch opens: no guess."""
    _, lm, images = load("fork_left_corner_ahead")
    assert lm.measure(images).lane_index == UNKNOWN_LANE


@pytest.mark.parametrize("lane_width_m", [0.709, 0.746, 0.783])  # nominal +- 5 %
@pytest.mark.parametrize("right_width_m, left_width_m", [(0.085, 0.036), (0.05, 0.10), (0.10, 0.05)])
def test_either_lane_of_a_two_lane_road_is_told_apart(lane_width_m, right_width_m, left_width_m):
    """The whole road drawn (both lanes); the robot in the right lane, then in the left one, at the
    same offsets and headings from its lane's centre: each view names its lane, and measures the
    offset from that lane's own centre; the lane spacing, once the line separation is learnt, is the
    drawn one within 1 cm plus what the lines' widths (not measured) put it off: half the difference of
    the widths from the nominal one."""
    fine, maps = synthetic_setup()
    road = synthetic_views.TwoLaneRoad(lane_width_m=lane_width_m, right_width_m=right_width_m,
                                       left_width_m=left_width_m)
    for lane_index, shift_m in ((RIGHT_LANE, 0.0), (LEFT_LANE, road.lane_spacing_m)):
        lm = LaneMeasurement(maps)
        for offset_m, heading_rad in VIEWS:
            r = lm.measure([synthetic_views.render(f, road, shift_m + offset_m, heading_rad) for f in fine])
            assert r.lane_index == lane_index, (offset_m, heading_rad)
            assert abs(r.lateral_offset_m - offset_m) < 0.03
            assert abs(math.degrees(r.heading_error_rad - heading_rad)) < 3.0
        centred = [synthetic_views.render(f, road, shift_m, 0.0) for f in fine]
        for _ in range(15):
            r = lm.measure(centred)
        widths_off_m = abs((left_width_m - right_width_m) - (0.036 - 0.085)) / 2
        assert r.lane_spacing_m == pytest.approx(road.lane_spacing_m, abs=0.01 + widths_off_m)


def test_a_lane_change_across_the_dashed_line_is_followed_frame_by_frame():
    """The robot crosses from the right lane to the left one in 4 cm steps, each frame fitted from the
    last one's prior: every frame names the lane it measures (the tracker may keep the right lane's
    lines in view, or take the left lane's) and puts the robot where it is from the right lane's
    centre (offset + lane index x lane spacing) within 3 cm; a fresh search at the end too."""
    fine, maps = synthetic_setup()
    road = synthetic_views.TwoLaneRoad()
    lm = LaneMeasurement(maps)
    prior = None
    for y_m in np.arange(0.0, road.lane_spacing_m + 1e-9, 0.04):
        images = [synthetic_views.render(f, road, y_m, math.radians(8.0)) for f in fine]
        r = lm.measure(images, prior)
        prior = lm.next_prior(r)
        assert r.lane_index != UNKNOWN_LANE, y_m
        assert abs(r.lateral_offset_m + r.lane_index * r.lane_spacing_m - y_m) < 0.03, y_m
    r = LaneMeasurement(maps).measure(images)
    assert r.lane_index == LEFT_LANE and abs(r.lateral_offset_m + r.lane_spacing_m - y_m) < 0.03


def test_darkest_channel_is_the_minimum_over_the_channels():
    rng = np.random.default_rng(7)
    img = rng.integers(0, 256, (120, 160, 3), dtype=np.uint8)
    darkest = _darkest_channel(img)
    assert darkest.dtype == np.uint8 and darkest.shape == (120, 160)
    assert np.array_equal(darkest, img.min(axis=2))
