"""conde_decision.avoidance on its own: which obstacles block the lane, the reference ramp, the
tracked lane's switches, the events."""
import math

import pytest

from conde_decision.avoidance import Avoidance, AvoidanceConfig, Obstacle

C = AvoidanceConfig()


def test_only_obstacles_reaching_into_the_own_lane_block_it():
    a = Avoidance()
    inside = Obstacle("box", 1.0, -0.3, 0.3)
    edge = Obstacle("cone", 1.0, C.block_half_width_m - 0.01, 0.4)  # a working-zone cone in the own lane
    other_lane = Obstacle("box", 1.0, 0.48, 1.08)
    assert a.blockers([inside, edge, other_lane]) == [inside, edge]


def test_obstacle_ahead_only_within_the_trigger_distance():
    a = Avoidance()
    assert a.step(0.0, True, 0.0, "own", [Obstacle("box", C.avoid_trigger_m + 0.1, -0.3, 0.3)]).events == []
    assert a.step(0.0, True, 0.1, "own", [Obstacle("box", C.avoid_trigger_m, -0.3, 0.3)]).events == ["obstacle_ahead"]


def test_the_reference_ramps_over_change_length_and_follows_a_switch_of_the_tracked_lane():
    a = Avoidance()
    a.step(0.0, True, 0.0, "own")
    # half of the ramp driven, heading 0.5 rad left: dead-reckoned 0.4 * sin(0.5) = 0.19 m left
    half = a.step(0.2, True, C.change_length_m / 2, "other", heading_error_rad=0.5)
    assert half.active and half.offset_ref_m == pytest.approx(C.lane_spacing_m / 2)
    assert half.own_lane_offset_m == pytest.approx(0.2)  # re-anchored on the tracker (within anchor_tolerance_m)
    # 0.3 m more at 0.5 rad: 0.344 m; the tracker now measures against the other lane
    switched = a.step(0.35 - C.lane_spacing_m, True, C.change_length_m / 2 + 0.3, "other", heading_error_rad=0.5)
    assert a.lane_shift_m == pytest.approx(C.lane_spacing_m)
    assert switched.own_lane_offset_m == pytest.approx(0.35)
    # 0.5 m more at asin(0.8): 0.4 m more, 0.75 m from the own lane; the tracker says 0.752
    done = a.step(-0.03, True, C.change_length_m / 2 + 0.8, "other", heading_error_rad=math.asin(0.8))
    assert done.own_lane_offset_m == pytest.approx(C.lane_spacing_m - 0.03)
    assert done.offset_ref_m == pytest.approx(C.lane_spacing_m) and "lane_changed" in done.events


def test_a_wrong_fit_does_not_move_the_dead_reckoned_offset():
    a = Avoidance()
    a.step(0.0, True, 0.0, "other")
    out = a.step(0.45, True, 0.1, "other")  # e.g. the fit caught one line of each lane; heading 0
    assert out.own_lane_offset_m == pytest.approx(0.0)  # not re-anchored: 0.45 m off the dead reckoning


def test_passed_after_the_far_end_and_back_on_the_own_lane():
    a = Avoidance()
    a.step(0.0, True, 0.0, "own", [Obstacle("box", 1.0, -0.3, 0.3)])
    far_m = 1.0 + C.box_depth_m + C.avoid_clearance_m
    a.step(0.4, True, 0.5, "other", heading_error_rad=0.8)  # the robot moves over (0.5 sin 0.8 = 0.36 m)
    assert "obstacle_passed" not in a.step(C.lane_spacing_m, True, far_m - 0.01, "other").events
    assert "obstacle_passed" in a.step(C.lane_spacing_m, True, far_m, "other").events
    a.step(0.4, True, far_m + C.change_length_m / 2, "own", heading_error_rad=-0.9)  # and back
    back = a.step(0.0, True, far_m + C.change_length_m, "own")
    assert back.events == ["lane_returned"] and not a.active


def test_outside_a_lane_change_the_tracker_is_passed_on():
    a = Avoidance()
    a.step(0.0, True, 0.0, "own")
    out = a.step(-0.6, True, 0.1, "own")  # e.g. a junction's lines
    assert not out.active and out.own_lane_offset_m == -0.6 and a.lane_shift_m == 0.0


def test_bad_config_names_the_field():
    with pytest.raises(ValueError, match="change_length_m"):
        AvoidanceConfig(change_length_m=0.0).check()
