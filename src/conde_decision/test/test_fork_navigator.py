"""ForkNavigator: the order chosen at each fork, and the end of the loop driven straight on."""
import math
from dataclasses import replace

import pytest

from conde_decision.decision_logic import DecisionConfig
from conde_decision.fork_navigator import ForkNavigator

# The 1-D model of the route has no camera corners: without the late fallback its turns begin at
# the stored distances (test_fork_navigator.py tests the fallback).
CONFIG = replace(DecisionConfig(), junction_fallback_m=0.0)
D = CONFIG.fork_distance_m


def fork(nav, order=None, yaw_rad=0.0):
    if order is not None:
        nav.on_direction(order)
    nav.on_crosswalk_left()
    assert nav.at_fork(D - 0.01, yaw_rad) == (None, "")
    return nav.at_fork(D, yaw_rad)


def test_forward_does_what_fork_forward_says():
    nav = ForkNavigator(CONFIG)
    assert fork(nav) == ("fork_straight", "")  # north fork: straight on
    nav.loop = None
    assert fork(nav)[0] == "fork_right"  # south fork: the branch (no corner seen: the fallback's note)
    assert nav.forks_passed == 2


def test_orders_are_used_up_and_impossible_ones_noted():
    nav = ForkNavigator(CONFIG)
    assert fork(nav, "left")[0] == "fork_left"
    assert nav.direction_order == "forward"
    assert fork(nav, "left") == ("fork_straight", "the panel ordered left, but this fork opens to the right: "
                                                  "keeping straight")
    assert nav.loop.merge == "left" and nav.loop.sign == -1.0
    assert nav.at_fork(10.0, 0.0) == (None, "")  # no fork pending


def test_no_fork_before_a_crosswalk_is_left():
    assert ForkNavigator(CONFIG).at_fork(None, 0.0) == (None, "")


def test_loop_exit_after_the_sweep_and_the_exit_distance():
    nav = ForkNavigator(replace(CONFIG, loop_exit_tolerance_rad=0.0))
    assert fork(nav, yaw_rad=None) == ("fork_straight", "")
    assert nav.loop_exit(None, 0.0) is None  # no heading yet
    assert nav.loop_exit(0.5 * math.pi, 0.0) is None  # the first heading is the loop's start
    assert nav.loop_exit(0.5 * math.pi + CONFIG.loop_sweep_rad - 0.01, 10.0) is None
    assert nav.loop_exit(0.5 * math.pi + CONFIG.loop_sweep_rad, 12.0) is None  # sweep complete at 12 m
    assert nav.loop_exit(0.5 * math.pi + CONFIG.loop_sweep_rad, 12.0 + CONFIG.loop_exit_m - 0.01) is None
    assert nav.loop_exit(0.5 * math.pi + CONFIG.loop_sweep_rad, 12.0 + CONFIG.loop_exit_m) == "merge_right"
    assert nav.loop is None and nav.loop_exit(0.0, 20.0) is None


def test_the_tolerance_leaves_its_arc_to_drive():
    nav = ForkNavigator(CONFIG)
    fork(nav, yaw_rad=0.0)
    tol = CONFIG.loop_exit_tolerance_rad
    assert nav.loop_exit(CONFIG.loop_sweep_rad - tol, 5.0) is None
    extra_m = tol * CONFIG.loop_lane_radii_m[0]
    assert nav.loop_exit(CONFIG.loop_sweep_rad, 5.0 + CONFIG.loop_exit_m + extra_m - 1e-6) is None
    assert nav.loop_exit(CONFIG.loop_sweep_rad, 5.0 + CONFIG.loop_exit_m + extra_m) == "merge_right"
    assert extra_m == pytest.approx(0.6678, abs=1e-3)  # 15 deg of the north loop's lane radius


# --- corners seen by the cameras ------------------------------------------------------------------

W = CONFIG.junction_window_m


def test_a_fork_fires_where_the_cameras_see_the_corner_of_the_branch_taken():
    nav = ForkNavigator(CONFIG)
    assert fork(nav) == ("fork_straight", "")  # north fork
    nav.loop = None
    nav.on_crosswalk_left()  # the south fork opens right; "forward" takes its branch there
    assert nav.at_fork(D - W - 0.01, 0.0, ("right",)) == (None, "")  # too early: not this fork's corner
    assert nav.at_fork(D - W + 0.1, 0.0, ()) == (None, "")
    assert nav.at_fork(D - W + 0.1, 0.0, ("left",)) == (None, "")  # the other side's corner
    assert nav.at_fork(D - W + 0.1, 0.0, ("right",)) == ("fork_right", "")
    assert nav.forks_passed == 2 and nav.direction_order == "forward"


def test_the_corner_of_a_branch_not_taken_changes_nothing():
    nav = ForkNavigator(CONFIG)
    nav.on_crosswalk_left()  # north fork, opens left, "forward" keeps straight
    assert nav.at_fork(D - 0.1, 0.0, ("left",)) == (None, "")
    assert nav.at_fork(D, 0.0, ("left",)) == ("fork_straight", "")
    nav.loop = None
    nav.on_direction("left")  # at the south fork (opens right): not obeyable, straight on
    nav.on_crosswalk_left()
    assert nav.at_fork(D - 0.1, 0.0, ("right",)) == (None, "")
    assert nav.at_fork(D, 0.0, ("right",))[0] == "fork_straight"


def test_a_loop_ends_where_the_cameras_see_the_corner_of_the_merge():
    nav = ForkNavigator(replace(CONFIG, loop_exit_tolerance_rad=0.0))
    fork(nav, yaw_rad=0.0)  # north fork straight: the loop ends with a right turn
    assert nav.loop_exit(CONFIG.loop_sweep_rad, 10.0) is None  # sweep complete at 10 m
    exit_m = 10.0 + CONFIG.loop_exit_m
    assert nav.loop_exit(CONFIG.loop_sweep_rad, exit_m - W - 0.01, ("right",)) is None
    assert nav.loop_exit(CONFIG.loop_sweep_rad, exit_m - W + 0.1, ("left",)) is None
    assert nav.loop_exit(CONFIG.loop_sweep_rad, exit_m - W + 0.1, ("right",)) == "merge_right"
    assert nav.loop is None


def test_a_marked_turn_not_seen_falls_back_after_the_stored_distance():
    """Turns (the cameras mark the corners of both sides) without a sighting begin
    junction_fallback_m after the stored distance, and say so; straight on at it."""
    config = DecisionConfig()
    fallback_m = config.junction_fallback_m
    assert fallback_m > 0
    nav = ForkNavigator(config)
    nav.on_direction("left")
    nav.on_crosswalk_left()
    assert nav.at_fork(D + fallback_m - 0.01, 0.0) == (None, "")
    assert nav.at_fork(D + fallback_m, 0.0) == (
        "fork_left", "fork_left at the fallback 2.10 m past the crosswalk: the cameras saw no corner")
    nav.on_crosswalk_left()  # the south fork, "forward": its branch, to the right
    assert nav.at_fork(D + fallback_m - 0.01, 0.0) == (None, "")
    assert nav.at_fork(D + fallback_m, 0.0)[0] == "fork_right"
    loop_nav = ForkNavigator(replace(config, loop_exit_tolerance_rad=0.0))
    loop_nav.on_crosswalk_left()
    assert loop_nav.at_fork(D, 0.0) == ("fork_straight", "")  # the north fork: the loop ends with a right merge
    assert loop_nav.loop_exit(config.loop_sweep_rad, 10.0) is None
    exit_m = 10.0 + config.loop_exit_m
    assert loop_nav.loop_exit(config.loop_sweep_rad, exit_m + fallback_m - 0.01) is None
    assert loop_nav.loop_exit(config.loop_sweep_rad, exit_m + fallback_m) == "merge_right"
    assert loop_nav.fallback_note.startswith("merge_right at the fallback")
    assert loop_nav.loop_exit(config.loop_sweep_rad, exit_m + fallback_m + 0.1) is None
    assert loop_nav.fallback_note == ""


def test_a_left_turn_fires_where_the_cameras_see_its_corner():
    """fork_left (north fork on "left") and merge_left (the south loop after a fork taken straight)
    begin at the corner seen, from junction_window_m before the stored distance on."""
    nav = ForkNavigator(replace(CONFIG, loop_exit_tolerance_rad=0.0))
    nav.on_direction("left")
    nav.on_crosswalk_left()
    assert nav.at_fork(D - W - 0.01, 0.0, ("left",)) == (None, "")  # too early: not this fork's corner
    assert nav.at_fork(D - W + 0.1, 0.0, ("right",)) == (None, "")  # the other side's corner
    assert nav.at_fork(D - W + 0.1, 0.0, ("left",)) == ("fork_left", "")
    nav.on_crosswalk_left()  # the south fork (opens right) on "forward" taken straight: fork_straight
    nav.on_direction("left")  # not obeyable there: straight on, the loop ends with a left merge
    assert nav.at_fork(D, 0.0)[0] == "fork_straight" and nav.loop.merge == "left"
    assert nav.loop_exit(-CONFIG.loop_sweep_rad, 10.0) is None  # the south loop turns clockwise
    exit_m = 10.0 + CONFIG.loop_exit_m
    assert nav.loop_exit(-CONFIG.loop_sweep_rad, exit_m - W - 0.01, ("left",)) is None
    assert nav.loop_exit(-CONFIG.loop_sweep_rad, exit_m - W + 0.1, ("right",)) is None
    assert nav.loop_exit(-CONFIG.loop_sweep_rad, exit_m - W + 0.1, ("left",)) == "merge_left"
    assert nav.fallback_note == ""


def test_turns_to_unmarked_sides_ignore_corner_sightings():
    nav = ForkNavigator(CONFIG, marked_sides=())
    fork(nav)
    nav.loop = None
    nav.on_crosswalk_left()
    assert nav.at_fork(D - 0.1, 0.0, ("right",)) == (None, "")
    assert nav.at_fork(D, 0.0, ("right",)) == ("fork_right", "")


# --- the order latched from the crosswalk's stop line to the fork ----------------------------------

def test_orders_read_past_the_stop_line_are_ignored_until_the_fork():
    """D2: the panel misread while the robot drives over the crosswalk does not change the order
    seen before the stop line; after the fork orders count again."""
    nav = ForkNavigator(CONFIG)
    nav.on_direction("left")
    nav.on_stop_line_passed()
    assert nav.on_direction("forward") == ("direction signal forward ignored: past the crosswalk's stop line "
                                           "the order left is kept")
    assert nav.on_direction("forward") == ""  # noted once
    assert nav.on_direction("left") == "" and nav.direction_order == "left"
    nav.on_crosswalk_left()
    assert nav.on_direction("right") != "" and nav.direction_order == "left"
    assert nav.at_fork(D, 0.0)[0] == "fork_left"
    assert not nav.order_latched
    assert nav.on_direction("right") == "" and nav.direction_order == "right"  # after the fork: counts


def test_orders_before_the_stop_line_count():
    """Standing before the crosswalk (stopped) or approaching it, every order replaces the last."""
    nav = ForkNavigator(CONFIG)
    for order in ("left", "forward", "right"):
        assert nav.on_direction(order) == ""
        assert nav.direction_order == order


# --- straight on across a fork that opens right ------------------------------------------------------

def test_the_course_is_held_across_a_right_fork_taken_straight():
    """The lane's edge line turns away into the branch: from junction_window_m before the stored
    fork distance to straight_crossing_m past it the robot holds its course."""
    nav = ForkNavigator(CONFIG)
    nav.on_crosswalk_left()
    assert not nav.holds_course(D)  # the north fork opens left: its edge line runs on
    assert nav.at_fork(D, 0.0)[0] == "fork_straight"
    assert not nav.holds_course(D + 0.1)
    nav.loop = None
    nav.on_direction("left")  # at the south fork (opens right): not obeyable, straight on
    nav.on_crosswalk_left()
    assert not nav.holds_course(None)
    assert not nav.holds_course(D - W - 0.01)
    assert nav.holds_course(D - W)
    assert nav.at_fork(D, 0.0)[0] == "fork_straight"
    assert nav.holds_course(D + CONFIG.straight_crossing_m - 0.01)
    assert not nav.tracker_may_be_on_the_other_lane()  # still crossing: the lane is not used at all
    assert not nav.holds_course(D + CONFIG.straight_crossing_m)
    assert nav.tracker_may_be_on_the_other_lane()
    nav.on_lane_measured(0.05, True, 0.2)
    assert nav.tracker_may_be_on_the_other_lane()  # in the loop: no end of the doubt
    nav.loop = None
    nav.on_lane_measured(-0.79, True, 0.2)
    nav.on_lane_measured(0.05, False, 0.2)
    assert nav.tracker_may_be_on_the_other_lane()  # the lane on the left, or one line only
    nav.on_lane_measured(0.05, True, 0.2)
    assert not nav.tracker_may_be_on_the_other_lane()  # the own lane again
    assert not nav.holds_course(D + 0.1)  # done
    nav.on_crosswalk_left()  # the north fork again
    nav.on_crosswalk_left()
    nav.forks_passed = 1  # the south fork on "forward": its branch, no crossing
    assert not nav.holds_course(D)


# --- the loop's sweep from the road's direction, robust to the robot's heading at the fork ---------

@pytest.mark.parametrize("error_deg", [-10.0, -6.0, 6.0, 10.0])
def test_the_sweep_counts_from_the_road_direction_seen_before_the_fork(error_deg):
    """D2, lap 2: the robot pointed about 6 deg left at the north fork (its lane follower swerved at
    the junction) and, counted from its heading there, the sweep never reached 265 deg: merge_right
    never fired at the loop's end.  Counted from the road's direction seen on the straight before the
    fork it is complete where the loop ends, and the right corner seen there starts the merge."""
    nav = ForkNavigator(CONFIG)
    nav.on_direction("right")  # not obeyable at the north fork: straight on
    nav.on_crosswalk_left()
    for k in range(20):  # the road's direction on the straight (heading less heading error), +-1 deg noise
        nav.on_road_direction(0.06 * k, math.radians(1.0 if k % 2 else -1.0))
    nav.on_road_direction(D - 0.1, math.radians(error_deg))  # inside the junction: not kept
    event, _ = nav.at_fork(D, math.radians(error_deg))
    assert event == "fork_straight" and nav.loop.yaw0_rad == pytest.approx(0.0, abs=math.radians(1.0))
    # the robot's heading wobbles 3 deg about the road's at the loop's end
    sweep_rad = CONFIG.loop_sweep_rad - math.radians(3.0)
    assert nav.loop_exit(sweep_rad, 10.0) is None  # armed at 10 m
    exit_m = 10.0 + CONFIG.loop_exit_m + CONFIG.loop_exit_tolerance_rad * CONFIG.loop_lane_radii_m[0]
    assert nav.loop_exit(sweep_rad, exit_m - W - 0.01, ("right",)) is None
    assert nav.loop_exit(sweep_rad, exit_m - 0.1, ("right",)) == "merge_right"


@pytest.mark.parametrize("error_deg", [6.0, 10.0])
def test_without_a_road_direction_the_wider_tolerance_still_arms_the_exit(error_deg):
    """No road direction seen before the fork (the robot's heading there counts): the 15 deg
    tolerance still lets a sweep short by a 6-10 deg heading error, plus 3 deg of wobble, arm the exit."""
    nav = ForkNavigator(CONFIG)
    fork(nav, yaw_rad=math.radians(error_deg))
    assert nav.loop.yaw0_rad == pytest.approx(math.radians(error_deg))
    sweep_rad = CONFIG.loop_sweep_rad - math.radians(3.0)
    assert nav.loop_exit(sweep_rad, 10.0) is None
    assert nav.loop.exit_mark_m == 10.0
    old = ForkNavigator(replace(CONFIG, loop_exit_tolerance_rad=0.087))  # the former 5 deg: never armed
    fork(old, yaw_rad=math.radians(error_deg))
    assert old.loop_exit(sweep_rad, 10.0) is None and old.loop.exit_mark_m is None


def test_a_right_merge_the_tracker_cannot_show_begins_at_the_stored_distance():
    """The tracker on the lane on the left does not measure the robot's own edge line, which marks
    the right turn's corner: no late fallback then, the merge begins at the stored distance."""
    nav = ForkNavigator(replace(CONFIG, loop_exit_tolerance_rad=0.0, junction_fallback_m=0.3))
    fork(nav, yaw_rad=0.0)
    assert nav.loop_exit(CONFIG.loop_sweep_rad, 10.0) is None
    exit_m = 10.0 + CONFIG.loop_exit_m
    assert nav.loop_exit(CONFIG.loop_sweep_rad, exit_m - 0.01, (), ("left",)) is None
    assert nav.loop_exit(CONFIG.loop_sweep_rad, exit_m, (), ("left",)) == "merge_right"
    assert nav.fallback_note == ""


def test_road_directions_are_kept_only_before_the_junction_and_since_the_last_crosswalk():
    nav = ForkNavigator(replace(CONFIG, min_road_direction_samples=2))
    nav.on_road_direction(0.5, 1.0)  # no crosswalk left yet: no fork pending
    nav.on_crosswalk_left()
    nav.on_road_direction(None, 1.0)
    nav.on_road_direction(0.5, math.nan)
    nav.on_road_direction(0.5, 0.1)
    assert nav.road_direction_rad() is None  # one sample
    nav.on_road_direction(D - W + 0.01, 0.3)  # in the junction's window
    nav.on_road_direction(D - W, 0.2)
    assert nav.road_direction_rad() == pytest.approx(0.15)
    nav.on_crosswalk_left()
    assert nav.road_direction_rad() is None
