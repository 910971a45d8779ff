"""conde_decision.avoidance on its own: which obstacles block the lane, the reference ramp, the
tracked lane's switches, the events."""
import math

import pytest

import recorded_sequence
from conde_decision.decision_logic import DecisionConfig
from conde_decision.avoidance import (Avoidance, AvoidanceConfig, EventDelay, Obstacle, rear_swing_heading_rad,
                                      return_remaining_m)

C = AvoidanceConfig()
MIN_LANE_CONFIDENCE = DecisionConfig().min_lane_confidence  # the decision's usable lane
# the plain ramp (no footprint, no limit on its direction's growth): for the tests of the ramp's and the
# landing's mechanics with steps of tens of cm (the gentle start: test_the_lane_change_starts_gently_*)
PLAIN = AvoidanceConfig(heading_ref_rate_per_m=1e9, rear_corner_back_m=1e-9, rear_corner_side_m=1e-9)


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
    a = Avoidance(PLAIN)
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
    a = Avoidance(PLAIN)
    a.step(0.0, True, 0.0, "own", [Obstacle("box", 1.0, -0.3, 0.3)])
    far_m = 1.0 + C.box_depth_m + C.avoid_clearance_m
    a.step(0.4, True, 0.5, "other", heading_error_rad=0.8)  # the robot moves over (0.5 sin 0.8 = 0.36 m)
    assert "obstacle_passed" not in a.step(C.lane_spacing_m, True, far_m - 0.01, "other").events
    assert "obstacle_passed" in a.step(C.lane_spacing_m, True, far_m, "other").events
    a.step(0.4, True, far_m + C.change_length_m / 2, "own", heading_error_rad=-0.9)  # and back
    # the tracker: on the own lane; the reference has landed (return_ease_per_m)
    back = a.step(0.0, True, far_m + C.change_length_m + 0.2, "own", lane_index=0)
    assert back.events == ["lane_returned"] and not a.active


def test_back_on_the_own_lane_only_heading_along_it():
    """Within settle_tolerance_m of the centre but still crossing at an angle the return goes on (ended
    there, the follower took the full offset and the robot overshot onto the edge line: D3, lap 2)."""
    a = Avoidance(PLAIN)
    a.step(0.0, True, 0.0, "own", [Obstacle("box", 1.0, -0.3, 0.3)])
    far_m = 1.0 + C.box_depth_m + C.avoid_clearance_m
    a.step(0.4, True, 0.5, "other", heading_error_rad=0.8)
    a.step(C.lane_spacing_m, True, far_m, "other")
    a.step(0.4, True, far_m + C.change_length_m / 2, "own", heading_error_rad=-0.9)
    # the reference has landed on the centre (return_ease_per_m): only the heading holds the return
    crossing = a.step(0.05, True, far_m + C.change_length_m + 0.2, "own",
                      heading_error_rad=-(C.return_heading_rad + 0.05), lane_index=0)
    assert crossing.offset_ref_m == 0.0
    assert crossing.events == [] and a.active
    along = a.step(0.03, True, far_m + C.change_length_m + 0.25, "own", heading_error_rad=-C.return_heading_rad / 2,
                   lane_index=0)
    assert along.events == ["lane_returned"] and not a.active


def test_outside_a_lane_change_the_tracker_is_passed_on():
    a = Avoidance()
    a.step(0.0, True, 0.0, "own")
    out = a.step(-0.6, True, 0.1, "own")  # e.g. a junction's lines
    assert not out.active and out.own_lane_offset_m == -0.6 and a.lane_shift_m == 0.0


def test_bad_config_names_the_field():
    with pytest.raises(ValueError, match="change_length_m"):
        AvoidanceConfig(change_length_m=0.0).check()


# --- the lane conde_tracking says it measured, the measured spacing, a lost lane ---------------------

def test_the_lane_index_places_the_robot_whatever_the_dead_reckoning_says():
    """The tracker on the other lane right after the change began (a 0.2 m offset: rounding the
    dead-reckoned offset would take it for the own lane): lane_index 1 puts it 0.2 m left of the
    own lane's centre; back on the own lane's lines, lane_index 0."""
    a = Avoidance()
    a.step(0.0, True, 0.0, "own")
    out = a.step(0.2 - 0.8, True, 0.1, "other", heading_error_rad=0.0, lane_index=1, lane_spacing_m=0.8)
    assert a.lane_shift_m == pytest.approx(0.8) and out.own_lane_offset_m == pytest.approx(0.2)
    out = a.step(0.25, True, 0.2, "other", lane_index=0, lane_spacing_m=0.8)
    assert a.lane_shift_m == 0.0 and out.own_lane_offset_m == pytest.approx(0.25)


def test_the_other_lane_is_the_measured_spacing_away():
    a = Avoidance()
    a.step(0.0, True, 0.0, "own", lane_spacing_m=0.82)
    out = a.step(0.0, True, 10.0, "other", lane_index=0, lane_spacing_m=0.82)
    assert out.offset_ref_m == pytest.approx(0.82)
    assert a.step(0.0, True, 10.1, "other", lane_index=1, lane_spacing_m=0.82).events == ["lane_changed"]


def test_without_a_usable_lane_the_offset_is_dead_reckoned_from_the_odometrys_turn():
    """The tracker republishes the last good heading (0.3 rad) when it loses the lane; the avoidance
    takes the lane's direction from that frame's odometry instead: the robot has turned back parallel
    to the lane (yaw 1.0 -> 0.7 rad), so the offset stays; without odometry it is held."""
    for yaw_rad in (1.0, None):
        a = Avoidance()
        a.step(0.1, True, 0.0, "other", heading_error_rad=0.3, lane_index=0, yaw_rad=yaw_rad)
        out = a.step(0.1, False, 0.5, "other", heading_error_rad=0.3, yaw_rad=None if yaw_rad is None else 0.7)
        assert out.own_lane_offset_m == pytest.approx(0.1)
    a = Avoidance()
    a.step(0.1, True, 0.0, "other", heading_error_rad=0.3, lane_index=0, yaw_rad=1.0)
    out = a.step(0.1, False, 0.5, "other", heading_error_rad=0.3, yaw_rad=1.0)  # still 0.3 rad to the lane
    assert out.own_lane_offset_m == pytest.approx(0.1 + 0.5 * math.sin(0.3))


def test_a_delayed_event_waits_for_a_state_that_takes_it_or_is_dropped():
    d = EventDelay(2.0)
    d.offer("fork_left", 10.0, taken=True)
    assert d.due(10.1, lambda e: True) == (None, "")  # taken at once: not kept
    d.offer("signal_stop", 10.0, taken=False)
    assert d.due(10.1, lambda e: True) == (None, "")  # not a fork or merge
    d.offer("merge_right", 10.0, taken=False)
    assert d.due(11.0, lambda e: False) == (None, "")
    assert d.due(11.5, lambda e: e == "merge_right") == ("merge_right", "")
    assert d.due(11.6, lambda e: True) == (None, "")  # fired once
    d.offer("fork_straight", 20.0, taken=False)
    event, note = d.due(22.1, lambda e: False)
    assert event is None and "fork_straight dropped" in note


def test_the_heading_reference_is_the_ramps_direction_while_it_moves():
    a = Avoidance(PLAIN)
    a.step(0.0, True, 0.0, "own", lane_spacing_m=0.8)
    ramp_rad = math.atan(0.8 / C.change_length_m)
    assert a.step(0.0, True, 0.1, "other", lane_index=0).heading_ref_rad == pytest.approx(ramp_rad)
    assert a.step(0.8, True, 0.1 + C.change_length_m, "other", lane_index=1).heading_ref_rad == 0.0  # on the lane
    back_rad = math.atan(0.8 / C.return_length_m)  # the way back is steeper
    assert a.step(0.0, True, 0.2 + C.change_length_m, "own", lane_index=1).heading_ref_rad == pytest.approx(-back_rad)
    # it lands: the last part of the way back turns along the lane, then the reference is on it
    landing = a.step(0.0, True, 0.2 + C.change_length_m + C.return_length_m, "own", lane_index=0)
    assert -back_rad < landing.heading_ref_rad < 0.0
    assert a.step(0.0, True, 0.2 + C.change_length_m + 2 * C.return_length_m, "own",
                  lane_index=0).heading_ref_rad == 0.0


def test_the_control_is_given_a_reference_near_the_robot():
    """The ramp runs ahead of a robot that lags: the control's reference stays within
    max_offset_error_m of the robot's offset (so that the control law does not turn it far off the
    lane); the ramp itself (offset_ref_m) goes on."""
    a = Avoidance(PLAIN)
    a.step(0.0, True, 0.0, "own")
    out = a.step(0.0, True, C.change_length_m / 2, "other", lane_index=0)
    assert out.offset_ref_m == pytest.approx(C.lane_spacing_m / 2)
    assert out.control_ref_m == pytest.approx(C.max_offset_error_m)
    out = a.step(0.5, True, C.change_length_m, "other", lane_index=0)
    assert out.control_ref_m == pytest.approx(0.5 + C.max_offset_error_m)
    out = a.step(-0.04, True, C.change_length_m + 0.1, "other", lane_index=1)
    assert out.offset_ref_m == out.control_ref_m == pytest.approx(C.lane_spacing_m)


def test_a_blocker_beside_the_robot_is_not_ahead():
    a = Avoidance()
    assert a.step(0.0, True, 0.0, "own", [Obstacle("box", 0.0, -0.3, 0.3)]).events == []
    assert a.step(0.0, True, 0.1, "own", [Obstacle("box", C.edge_seen_from_m, -0.3, 0.3)]).events == ["obstacle_ahead"]


def test_in_a_left_curve_the_box_is_passed_after_a_shorter_drive_beside_it():
    """On the other lane, 0.8 m inside a left curve of the own lane of radius 2.6 m (the robot's arc
    1.8 m): a box's depth along the own lane is passed after 1.8 / 2.6 of it driven."""
    far_by_arc = []
    for turning in (False, True):
        a = Avoidance()
        a.step(0.0, True, 0.0, "own", [Obstacle("box", 1.0, -0.3, 0.3)], lane_index=0, lane_spacing_m=0.8, yaw_rad=0.0)
        s_m = 0.0
        while True:  # on the other lane from the start (a robot that changed lanes at once)
            s_m += 0.01
            out = a.step(-0.0, True, s_m, "other", lane_index=1, lane_spacing_m=0.8,
                         yaw_rad=s_m / 1.8 if turning else 0.0)
            if "obstacle_passed" in out.events:
                break
        far_by_arc.append(s_m)
    straight_m, curve_m = far_by_arc
    assert straight_m == pytest.approx(1.0 + C.box_depth_m + C.avoid_clearance_m, abs=0.02)
    assert curve_m == pytest.approx(straight_m * 1.8 / 2.6, abs=0.03)


def test_the_way_back_is_laid_along_the_lane_and_lands_on_it():
    """return_remaining_m: at the ramp's slope per metre along the lane, then exponentially."""
    slope = C.lane_spacing_m / C.return_length_m
    knee_m = slope / C.return_ease_per_m
    assert return_remaining_m(0.782, 0.3, slope, C.return_ease_per_m) == pytest.approx(0.782 - 0.3 * slope)
    assert return_remaining_m(knee_m, 0.5, slope, C.return_ease_per_m) == pytest.approx(
        knee_m * math.exp(-0.5 * C.return_ease_per_m))
    one_go = return_remaining_m(0.782, 1.2, slope, C.return_ease_per_m)
    assert one_go == pytest.approx(return_remaining_m(return_remaining_m(0.782, 0.4, slope, C.return_ease_per_m),
                                                      0.8, slope, C.return_ease_per_m))
    # driven at 60 deg off the lane, the way back advances by half the distance driven
    a = Avoidance(PLAIN)
    a.step(0.0, True, -2.0, "other", lane_index=1)
    a.step(0.0, True, 0.1, "other", lane_index=1)  # on the other lane
    out = a.step(-0.1, True, 0.3, "own", lane_index=1, heading_error_rad=-math.pi / 3)
    assert out.offset_ref_m == pytest.approx(0.782 - slope * 0.1)


def _return_in_closed_loop(config, heading_seen=1.0):
    """The robot on the other lane of a straight road, told to come back (lane own), steered by
    conde_control's law at 30 Hz at 0.5 m/s; exact measurements of the lane it is nearer to, but for
    the heading error: heading_seen times the true one (the tracker read 0.85 rad for a true 1.03).
    Returns (the largest overshoot past the own lane's centre [m], |heading error| when the
    avoidance said lane_returned [rad])."""
    from conde_control.control_law import ControlConfig, LaneFollowingController, Reference

    control = LaneFollowingController(ControlConfig())
    a = Avoidance(config)
    spacing_m, dt_s = 0.782, 1.0 / 30.0
    y_m, heading_rad, s_m, v_mps = spacing_m, 0.0, 0.0, 0.5
    control.v_mps = v_mps
    for k in range(101):  # on the other lane (its reference moved over in steps of 2 cm)
        a.step(0.0, True, s_m - 2.0 + 0.02 * k, "other", lane_index=1, lane_spacing_m=spacing_m)
    overshoot_m, returned_heading_rad = 0.0, None
    for _ in range(int(6.0 / dt_s)):
        index = 1 if y_m > spacing_m / 2 else 0
        seen_rad = heading_seen * heading_rad
        out = a.step(y_m - index * spacing_m, True, s_m, "own", heading_error_rad=seen_rad, lane_index=index,
                     lane_spacing_m=spacing_m)
        if "lane_returned" in out.events:
            returned_heading_rad = abs(heading_rad)
        offset_m = out.own_lane_offset_m if out.active else y_m - index * spacing_m
        v, omega = control.update(Reference(offset_m, out.control_ref_m, seen_rad, out.heading_ref_rad, v_mps), dt_s)
        s_m += v * dt_s
        y_m += v * dt_s * math.sin(heading_rad)
        heading_rad += omega * dt_s
        overshoot_m = max(overshoot_m, -y_m)
    assert returned_heading_rad is not None
    return overshoot_m, returned_heading_rad


def test_the_way_back_ends_heading_along_the_lane_without_overshoot():
    """D4 v2 (recorded, ODE): the way back ran 1 m of distance driven, so the robot kept pace only at
    asin(0.78) = 51 deg off the lane (59 deg by ground truth); it reached the own lane's centre at that
    angle, went 10 cm past it and touched the outer line (the old code here: 4.9 cm past, 0.96 rad
    when lane_returned).  Laid along the lane and landing, it arrives parallel to the lane: 0.6 cm
    past (3.4 cm with the heading under-read), 0.03 rad."""
    for heading_seen in (1.0, 0.83):
        overshoot_m, heading_rad = _return_in_closed_loop(C, heading_seen)
        assert overshoot_m < 0.04 and heading_rad < 0.1
    # without the landing the robot reaches the lane's centre at the ramp's angle and goes on past it
    # (lane_returned itself waits for the heading along the lane, return_heading_rad: the overshoot shows it)
    abrupt = AvoidanceConfig(return_ease_per_m=1e6, return_end_m=1e-6)
    abrupt_overshoot_m, _ = _return_in_closed_loop(abrupt, 0.83)
    assert abrupt_overshoot_m > 0.06


def _replay(config, name, t1_s=math.inf):
    """Feeds the lane rows of fixtures/<name> (written by fixtures/make_avoidance_sequence.py) up to
    t1_s [s] through an avoidance of that config as the decision does; yields (row, AvoidanceStep,
    the heading error given to the control [rad]: the measured one, or the dead-reckoned one where the
    measurement is not taken; nan without either)."""
    yaw_rad, avoidance = None, Avoidance(config)
    for row in recorded_sequence.load(name):
        if row["kind"] != "lane" or row["t_s"] > t1_s:
            continue
        lane = recorded_sequence.lane_of(row)
        # the decision's odometry heading is unwrapped
        yaw_rad = row["yaw_rad"] if yaw_rad is None else yaw_rad + math.remainder(row["yaw_rad"] - yaw_rad, 2 * math.pi)
        lane_ok = (math.isfinite(lane.lateral_offset_m) and math.isfinite(lane.heading_error_rad)
                   and lane.confidence >= MIN_LANE_CONFIDENCE)
        out = avoidance.step(lane.lateral_offset_m, lane_ok, row["odom_path_m"], row["command_lane"], (),
                             lane.heading_error_rad, lane.confidence >= 1.0, lane.lane_index, lane.lane_spacing_m,
                             yaw_rad)
        heading_rad = out.heading_error_rad if out.lane_rejected else lane.heading_error_rad if lane_ok else math.nan
        yield row, out, heading_rad


def _replay_recorded_change(config):
    """fixtures/d3_bullet_track2_north_loop_avoidance_sequence.csv (D3, Bullet, track and placement
    seed 2, lap 1: the lane change round the north loop's box and the start of the way back): the
    largest error [m, rad] against ground truth of the own lane's offset and of the heading error the
    control is given, and how many measurements were not taken."""
    worst_offset_m = worst_heading_rad = 0.0
    rejected = 0
    for row, out, heading_rad in _replay(config, "d3_bullet_track2_north_loop_avoidance_sequence.csv"):
        rejected += out.lane_rejected
        if math.isfinite(out.own_lane_offset_m):
            worst_offset_m = max(worst_offset_m, abs(out.own_lane_offset_m - row["truth_offset_m"]))
        if math.isfinite(heading_rad):
            worst_heading_rad = max(worst_heading_rad, abs(heading_rad - row["truth_heading_rad"]))
    return worst_offset_m, worst_heading_rad, rejected


def test_a_fit_off_the_odometrys_heading_is_not_taken_while_changing_lanes():
    """Recorded (Bullet, track seed 2): the way back turned the robot 1.1 rad off the lane (ground
    truth); there the tracker read -0.45 rad, then +0.43 (at -1.23) and lane 0 with the robot on the
    lane's centre line (0.09 m for 0.41); taken, they put the robot 0.42 m and 3.1 rad off in the
    avoidance's frame and the control turned it round on the road.  Not taken (their heading is more
    than heading_gate_rad from the odometry's), offset and heading stay within 0.14 m and 0.29 rad."""
    worst_offset_m, worst_heading_rad, rejected = _replay_recorded_change(C)
    assert worst_offset_m < 0.16 and worst_heading_rad < 0.35 and rejected > 0
    ungated = AvoidanceConfig(heading_gate_rad=100.0)
    worst_offset_m, worst_heading_rad, rejected = _replay_recorded_change(ungated)
    assert worst_offset_m > 0.3 and worst_heading_rad > 1.0 and rejected == 0


def _heading_errors_on_the_way_back(config, name, t0_s, t1_s):
    """The errors [rad] against ground truth of the heading the control is given, from t0_s to t1_s [s]
    of fixtures/<name>."""
    return [abs(heading_rad - row["truth_heading_rad"]) for row, _, heading_rad in _replay(config, name, t1_s)
            if row["t_s"] >= t0_s and math.isfinite(heading_rad)]


def test_a_run_of_drifting_fits_does_not_carry_the_lanes_direction_along():
    """Recorded (D3, ODE, track and placement seed 11, lap 2; fixtures/d3_ode_track11_north_loop_return_sequence.csv,
    make_avoidance_sequence.py run.bag 107.0 119.5 -0.317047 5.298448 2.483866: the north loop's outer
    lane): on the way back, crossing the dashed line in the curve, the tracker read -0.64, -0.79, -0.90,
    -1.07 ... -1.25 rad in 0.1 m, ground truth about -0.5.  Each was within the gate of the one before,
    so each was taken and moved the lane's direction, and the gate with it: the good fits after them
    (-0.26 rad) were then rejected, the control was given -1.2 rad and turned the robot round.  The lane's
    direction now follows the fits by at most lane_turn_rad_per_m per m driven."""
    name = "d3_ode_track11_north_loop_return_sequence.csv"
    errors_rad = _heading_errors_on_the_way_back(C, name, 113.0, 114.45)
    assert len(errors_rad) > 40 and sum(e > 0.3 for e in errors_rad) <= 4 and max(errors_rad) < 0.6
    unbounded = _heading_errors_on_the_way_back(AvoidanceConfig(lane_turn_rad_per_m=1000.0), name, 113.0, 114.45)
    assert sum(e > 0.3 for e in unbounded) >= 10 and max(unbounded) > 0.7


def test_the_lanes_direction_follows_the_fits_taken_at_a_bounded_rate():
    a = Avoidance()
    a.step(0.0, True, 0.0, "other", heading_error_rad=0.0, yaw_rad=0.0)  # the lane along the odometry's 0
    travelled_m, frame_m = 0.0, 0.02
    for k in range(1, 8):  # fits drifting by 0.15 rad per frame, the robot's heading unchanged
        travelled_m += frame_m
        out = a.step(0.0, True, travelled_m, "other", heading_error_rad=-0.15 * k, yaw_rad=0.0)
    # the lane's direction moved at most lane_turn_rad_per_m per m (three fits taken, 0.04 rad each); the
    # fits that drifted on are not taken
    assert out.lane_rejected
    assert a.lane_yaw_rad == pytest.approx(3 * C.lane_turn_rad_per_m * frame_m)
    # after a stretch without a fit taken, the next one is taken whole (over 1.08 m the gate has widened by
    # 1.08 rad and the direction may move by 2.16 rad)
    a.step(0.0, True, travelled_m + 1.0, "other", heading_error_rad=-0.8, yaw_rad=0.0)
    assert a.lane_yaw_rad == pytest.approx(0.8)
    # outside a lane change the direction is the last fit's
    b = Avoidance()
    b.step(0.0, True, 0.0, "own", heading_error_rad=0.0, yaw_rad=0.0)
    b.step(0.0, True, 0.02, "own", heading_error_rad=-0.6, yaw_rad=0.0)
    assert b.lane_yaw_rad == pytest.approx(0.6)


def test_the_heading_gate_widens_with_the_distance_driven_since_the_last_fit_taken():
    a = Avoidance()
    a.step(0.0, True, 0.0, "other", heading_error_rad=0.1, yaw_rad=0.0)  # lane direction -0.1 by odometry
    out = a.step(0.0, True, 0.05, "other", heading_error_rad=0.1 + C.heading_gate_rad + 0.1, yaw_rad=0.0)
    assert out.lane_rejected and out.heading_error_rad == pytest.approx(0.1)
    # 0.5 m on without a fit taken: the lane may have turned 0.5 rad more under the robot
    out = a.step(0.0, True, 0.5, "other", heading_error_rad=0.1 + C.heading_gate_rad + 0.1, yaw_rad=0.0)
    assert not out.lane_rejected and out.heading_error_rad == pytest.approx(0.6)
    # outside a lane change nothing is gated
    b = Avoidance()
    b.step(0.0, True, 0.0, "own", heading_error_rad=0.0, yaw_rad=0.0)
    assert not b.step(0.0, True, 0.05, "own", heading_error_rad=1.5, yaw_rad=0.0).lane_rejected


def test_the_heading_gate_config_is_checked():
    with pytest.raises(ValueError, match="heading_gate_rad"):
        AvoidanceConfig(heading_gate_rad=-1.0).check()


def test_the_rear_swing_bound_is_the_heading_at_which_the_rear_corner_reaches_the_room():
    heading_rad = rear_swing_heading_rad(0.3, C.rear_corner_back_m, C.rear_corner_side_m)
    reach_m = C.rear_corner_back_m * math.sin(heading_rad) + C.rear_corner_side_m * math.cos(heading_rad)
    assert 0.0 < heading_rad < 0.5 and reach_m == pytest.approx(0.3)
    assert rear_swing_heading_rad(0.1, C.rear_corner_back_m, C.rear_corner_side_m) == 0.0  # no room
    assert rear_swing_heading_rad(1.0, C.rear_corner_back_m, C.rear_corner_side_m) == pytest.approx(math.pi / 2)


def _change_and_back_in_closed_loop(config, spacing_m):
    """The robot on the own lane's centre of a straight road, told to change lanes (lane other) and,
    once lane_changed, to come back, steered by conde_control's law at 30 Hz at 0.5 m/s on exact
    measurements.  Returns (how far inside the start lane's outer line's centre the rear corner on
    the far side came at worst on the change and on the way back [m], the robot's offset 1.6 m after
    the change began (a box's near edge when obstacle_ahead) [m], the largest step of the heading
    reference from one measurement to the next [rad])."""
    from conde_control.control_law import ControlConfig, LaneFollowingController, Reference

    control = LaneFollowingController(ControlConfig())
    a = Avoidance(config)
    dt_s, v_mps = 1.0 / 30.0, 0.5
    y_m, heading_rad, s_m = 0.0, 0.0, 0.0
    control.v_mps = v_mps
    a.step(0.0, True, s_m, "own", lane_index=0, lane_spacing_m=spacing_m)
    back_m, side_m = C.rear_corner_back_m, C.rear_corner_side_m
    inside_m, y_at_box_m, jump_rad, last_ref_rad, lane = [9.0, 9.0], None, 0.0, 0.0, "other"
    for _ in range(int(10.0 / dt_s)):
        index = 1 if y_m > spacing_m / 2 else 0
        out = a.step(y_m - index * spacing_m, True, s_m, lane, heading_error_rad=heading_rad, lane_index=index,
                     lane_spacing_m=spacing_m)
        if lane == "other" and "lane_changed" in out.events:
            lane = "own"
        v, omega = control.update(Reference(out.own_lane_offset_m, out.control_ref_m, heading_rad, out.heading_ref_rad,
                                            v_mps), dt_s)
        s_m += v * dt_s
        jump_rad = max(jump_rad, abs(out.heading_ref_rad) - abs(last_ref_rad))
        last_ref_rad = out.heading_ref_rad
        y_m += v * dt_s * math.sin(heading_rad)
        heading_rad += omega * dt_s
        if y_at_box_m is None and s_m >= 1.6:
            y_at_box_m = y_m
        if lane == "other":  # turning left: the right rear corner, against the own lane's right line
            corner_m = y_m - back_m * math.sin(heading_rad) - side_m * math.cos(heading_rad)
            inside_m[0] = min(inside_m[0], corner_m + spacing_m / 2)
        else:  # turning right: the left rear corner, against the other lane's left line
            corner_m = y_m - back_m * math.sin(heading_rad) + side_m * math.cos(heading_rad)
            inside_m[1] = min(inside_m[1], 1.5 * spacing_m - corner_m)
    assert not a.active  # back on the own lane
    return inside_m, y_at_box_m, jump_rad


def test_the_lane_change_starts_gently_and_its_rear_stays_off_the_outer_lines():
    """D3, Bullet, track seed 4 (lane 0.713 m between the lines, 0.17 m of room beside Conde): the
    ramp's direction jumped from 0 to 0.46 rad (0.66 on the way back) at once, Conde turned nearly on
    the spot and its rear corner, 0.443 m behind base_footprint, swung 0.19 m out and touched the
    outer line.  The direction now grows with the distance driven, bounded by the rear corner's room:
    it stays more than half a line (0.05 m) plus a margin inside the lines' centres, where the plain
    ramp's rear reaches within 0.07 m of the own lane's right line and past the other lane's left one,
    and the robot is still on the other lane when it reaches a box seen at avoid_trigger_m."""
    for spacing_m in (0.782, 0.75):
        inside_m, y_at_box_m, jump_rad = _change_and_back_in_closed_loop(C, spacing_m)
        assert min(inside_m) > 0.06 and inside_m[0] > C.rear_clearance_m - 0.01, inside_m
        assert y_at_box_m > spacing_m - 0.1
        assert jump_rad <= C.min_ramp_rad + 1e-6  # its first step, then it grows with the distance driven
        plain_inside_m, _, plain_jump_rad = _change_and_back_in_closed_loop(PLAIN, spacing_m)
        assert plain_inside_m[0] < 0.07 and plain_inside_m[1] < 0.0, plain_inside_m
        assert plain_jump_rad > 0.45
