"""conde_decision.avoidance on its own: which obstacles block the lane, the reference ramp, the
tracked lane's switches, the events."""
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
    travelled = 0.0
    a.step(0.0, True, travelled, "own")
    travelled += C.change_length_m / 2
    half = a.step(0.3, True, travelled, "other")
    assert half.offset_ref_m == pytest.approx(C.lane_spacing_m / 2)
    # the tracker now measures against the other lane: its offset jumps by one spacing
    jumped = a.step(0.35 - C.lane_spacing_m, True, travelled + 0.01, "other")
    assert a.lane_shift_m == pytest.approx(C.lane_spacing_m)
    assert jumped.own_lane_offset_m == pytest.approx(0.35)
    assert jumped.offset_ref_m == pytest.approx(a.ref_m - C.lane_spacing_m)
    travelled += C.change_length_m
    done = a.step(-0.01, True, travelled, "other")
    assert done.offset_ref_m == pytest.approx(0.0) and "lane_changed" in done.events


def test_passed_after_the_far_end_and_back_on_the_own_lane():
    a = Avoidance()
    a.step(0.0, True, 0.0, "own", [Obstacle("box", 1.0, -0.3, 0.3)])
    far_m = 1.0 + C.box_depth_m + C.avoid_clearance_m
    a.step(0.4, True, 0.5, "other")  # the robot moves over gradually
    assert "obstacle_passed" not in a.step(C.lane_spacing_m, True, far_m - 0.01, "other").events
    assert "obstacle_passed" in a.step(C.lane_spacing_m, True, far_m, "other").events
    a.step(0.4, True, far_m + C.change_length_m / 2, "own")  # the robot moves back gradually
    back = a.step(0.0, True, far_m + C.change_length_m, "own")
    assert back.events == ["lane_returned"] and not a.active


def test_a_jump_of_no_whole_lane_spacing_is_not_a_switch_of_lanes():
    a = Avoidance()
    a.step(0.0, True, 0.0, "other")
    a.step(0.5, True, 0.1, "other")  # e.g. the fit caught one line of each lane
    assert a.lane_shift_m == 0.0


def test_no_jump_is_taken_outside_a_lane_change():
    a = Avoidance()
    a.step(0.0, True, 0.0, "own")
    a.step(-0.6, True, 0.1, "own")  # e.g. a junction's lines: not a lane switch
    assert a.lane_shift_m == 0.0


def test_bad_config_names_the_field():
    with pytest.raises(ValueError, match="change_length_m"):
        AvoidanceConfig(change_length_m=0.0).check()
