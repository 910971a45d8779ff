"""Where a junction's arc ends on the lane seen (arc_end.py, the event lane_aligned): a fresh fit of
one frame is not trusted, a confirmed one ends the turn.  On recorded sequences of D1 track seed 1
(ODE; fixtures/make_lane_sequence.py from a rosbag of that run) and on made-up measurements."""

import math
from dataclasses import replace

import pytest

from conde_decision.arc_end import ArcEnd
from conde_decision.decision_logic import RIGHT, DecisionConfig, DecisionLogic
from conde_decision.state_machine import parse_state_machine
from recorded_sequence import load, replay

# the order is given once, as one message: it counts at once, driving too (test_order_gate.py: the hold)
CONFIG = replace(DecisionConfig(), order_hold_s=0.0, order_crosswalk_range_m=0.0)
RADIUS_M, DISTANCE_M = 0.609, 0.957  # conde_states.yaml's turn_right
SWEEP_RAD = DISTANCE_M / RADIUS_M
# the right turn into the south loop, from its first frame: lap 1 (a one-frame false alignment ended the
# turn at 50.800 s, 42 deg into it) and lap 2 (the real lane, seen from 135.17 s on)
LAP1 = "d1_seed1_lap1_south_turn_sequence.csv"
LAP2 = "d1_seed1_lap2_south_turn_sequence.csv"
OLD_END_LAP1_S = 50.800


def turn_right_logic():
    """A DecisionLogic whose "right" order starts conde_states.yaml's right turn at once."""
    spec = parse_state_machine({"initial": "follow_lane", "states": {
        "follow_lane": {"command": {"speed": "cruise"}, "on": {"signal_right": "turn_right"}},
        "turn_right": {"command": {"speed": "cruise", "branch": "right", "radius_m": RADIUS_M,
                                   "distance_m": DISTANCE_M},
                       "on": {"distance_elapsed": "return", "lane_aligned": "return"}}}}, "inline")
    return DecisionLogic(spec, CONFIG)


def replay_turn(name, until_s=math.inf):
    """The recorded turn through DecisionLogic, entered at its first frame; [(t_s, row, out)]."""
    rows = [r for r in load(name) if r["t_s"] <= until_s]
    logic = turn_right_logic()
    logic.on_odometry(rows[0]["yaw_rad"], rows[0]["odom_path_m"])
    logic.on_signal(RIGHT, 1.0)
    assert logic.state == "turn_right"
    return replay(logic, rows, stop=lambda t_s, out: out.state != "turn_right"), rows[0]


def test_the_recorded_false_alignment_is_one_confident_frame_along_the_robot():
    """The fixture holds the fault: at 50.800 s, past half the arc, a fit with both lines and a heading
    error within lane_aligned_rad (the old criterion), of a lane far from the one the turn leads to."""
    row = next(r for r in load(LAP1) if r["t_s"] == pytest.approx(OLD_END_LAP1_S))
    start = load(LAP1)[0]
    assert row["odom_path_m"] - start["odom_path_m"] >= 0.5 * DISTANCE_M
    assert row["confidence"] == 1.0 and abs(row["heading_error_rad"]) <= CONFIG.lane_aligned_rad
    turned_rad = start["yaw_rad"] - row["yaw_rad"]
    assert turned_rad < 0.5 * SWEEP_RAD  # 42 deg of 90


def test_a_one_frame_false_alignment_early_in_the_arc_does_not_end_the_turn():
    outputs, _ = replay_turn(LAP1, until_s=OLD_END_LAP1_S + 0.01)
    assert outputs[-1][0] == pytest.approx(OLD_END_LAP1_S)
    assert all("lane_aligned" not in out.events for _, _, out in outputs)
    assert outputs[-1][2].state == "turn_right"


def test_a_real_alignment_ends_the_turn_within_a_few_frames_of_the_new_lane():
    """Lap 2: the lane the turn leads to is seen from 135.17 s on (its direction within
    lane_aligned_direction_rad of the arc's end); the turn ends lane_aligned_frames later at the
    latest once the sweep's minimum is turned, heading toward the lane's centre as the follower would."""
    outputs, start = replay_turn(LAP2)
    t_s, row, out = outputs[-1]
    assert out.transitions == [("turn_right", "lane_aligned", "follow_lane")]
    turned_rad = start["yaw_rad"] - row["yaw_rad"]
    assert CONFIG.lane_aligned_min_sweep * SWEEP_RAD <= turned_rad < SWEEP_RAD
    first_seen_s = 135.167
    frames = [t for t, _, _ in outputs if t >= first_seen_s - 1e-6]
    assert len(frames) <= CONFIG.lane_aligned_frames + 1
    assert row["lateral_offset_m"] < -0.1 and row["heading_error_rad"] > 0.2  # inside the turn, heading back to it
    assert row["odom_path_m"] - start["odom_path_m"] < DISTANCE_M  # before the arc's stored length


def arc(updates, arc_end=None, side=-1.0):
    """Feeds (turned_rad, offset_m, heading_error_rad, confidence) to an ArcEnd started at yaw 0;
    returns its answers."""
    arc_end = arc_end or ArcEnd(CONFIG)
    arc_end.start(0.0)
    return [arc_end.update(side, RADIUS_M, DISTANCE_M, t * RADIUS_M, side * t, o, h, c) for t, o, h, c in updates]


def on_the_new_lane(turned_rad, offset_m=0.0):
    """A measurement of the lane the right arc leads to, with the robot turned_rad into the arc."""
    return turned_rad, offset_m, SWEEP_RAD - turned_rad, 1.0


def test_a_confirmed_lane_at_the_arc_end_ends_it_on_the_last_confirming_frame():
    t0 = SWEEP_RAD - CONFIG.lane_aligned_rad / 2
    answers = arc([on_the_new_lane(t0 + 0.001 * k) for k in range(CONFIG.lane_aligned_frames)])
    assert answers == [False] * (CONFIG.lane_aligned_frames - 1) + [True]


@pytest.mark.parametrize("spoil", ["one frame off the end direction", "one frame with one line",
                                   "offsets that jump", "too early in the sweep"])
def test_no_end_without_a_confirmed_track_of_the_new_lane(spoil):
    t0 = SWEEP_RAD - CONFIG.lane_aligned_rad / 2
    frames = [on_the_new_lane(t0 + 0.001 * k) for k in range(CONFIG.lane_aligned_frames)]
    middle = CONFIG.lane_aligned_frames // 2
    t, o, h, c = frames[middle]
    if spoil == "one frame off the end direction":
        frames[middle] = (t, o, h + CONFIG.lane_aligned_direction_rad + 0.01, c)
    elif spoil == "one frame with one line":
        frames[middle] = (t, o, h, 0.5)
    elif spoil == "offsets that jump":
        frames = [(t, CONFIG.lane_aligned_spread_m + 0.01 if k % 2 else 0.0, h, c)
                  for k, (t, o, h, c) in enumerate(frames)]
    else:  # a lane within the tolerated direction, the robot heading to it as the follower would, too soon
        early_rad = CONFIG.lane_aligned_min_sweep * SWEEP_RAD - 0.05
        lane_rad = SWEEP_RAD - CONFIG.lane_aligned_direction_rad + 0.02  # as the right arc turns [rad]
        frames = [(early_rad + 0.001 * k, -0.15, lane_rad - early_rad - 0.001 * k, 1.0)
                  for k in range(CONFIG.lane_aligned_frames)]
        assert arc([(t + 0.06, o, h - 0.06, c) for t, o, h, c in frames])[-1]  # a little later: the end
    assert not any(arc(frames))


def test_the_turn_ends_heading_toward_the_lane_centre_as_the_follower_would():
    """13 cm inside a right turn the follower steers 3.6 rad/m x 0.13 m back (at most 0.4 rad): the arc
    ends once the robot heads that much toward the centre (or less: turned past it), not only when it
    is parallel to the lane."""
    offset_m = -0.13
    approach_rad = min(CONFIG.lane_aligned_max_approach_rad, -CONFIG.lane_aligned_approach_per_m * offset_m)
    arc_end = ArcEnd(CONFIG)
    assert arc_end.approach_rad(offset_m) == pytest.approx(approach_rad)
    assert arc_end.approach_rad(-1.0) == pytest.approx(CONFIG.lane_aligned_max_approach_rad)
    assert arc_end.approach_rad(1.0) == pytest.approx(-CONFIG.lane_aligned_max_approach_rad)
    n = CONFIG.lane_aligned_frames
    still_turning = [on_the_new_lane(SWEEP_RAD - approach_rad - CONFIG.lane_aligned_rad - 0.05 + 0.001 * k, offset_m)
                     for k in range(n)]
    assert not any(arc(still_turning, arc_end))
    at_approach = [on_the_new_lane(SWEEP_RAD - approach_rad + 0.001 * k, offset_m) for k in range(n)]
    assert arc(at_approach, arc_end)[-1]
    parallel = [on_the_new_lane(SWEEP_RAD - 0.001 * k, offset_m) for k in range(n)]  # turned past it
    assert arc(parallel, arc_end)[-1]
    centred = [on_the_new_lane(SWEEP_RAD - approach_rad + 0.001 * k, 0.0) for k in range(n)]  # on the centre
    assert not any(arc(centred, arc_end))  # ... the follower heads along the lane: turn on


def test_a_left_arc_and_an_arc_without_odometry_are_judged_alike():
    n = CONFIG.lane_aligned_frames
    t0 = SWEEP_RAD - 0.02
    left = ArcEnd(CONFIG)
    left.start(1.0)
    answers = [left.update(1.0, RADIUS_M, DISTANCE_M, 0.0, 1.0 + t0 + 0.001 * k, 0.0, -(SWEEP_RAD - t0 - 0.001 * k),
                           1.0) for k in range(n)]
    assert answers[-1] and not any(answers[:-1])
    blind = ArcEnd(CONFIG)
    blind.start(None)  # no odometry: the heading is the commanded arc's, in_arc_m / radius_m
    answers = [blind.update(-1.0, RADIUS_M, DISTANCE_M, (t0 + 0.001 * k) * RADIUS_M, None, 0.0,
                            SWEEP_RAD - t0 - 0.001 * k, 1.0) for k in range(n)]
    assert answers[-1] and not any(answers[:-1])


@pytest.mark.parametrize("name, value", [("lane_aligned_frames", 0), ("lane_aligned_frames", 1.5),
                                         ("lane_aligned_min_sweep", -0.1), ("lane_aligned_approach_per_m", -1.0)])
def test_bad_confirmation_settings_are_named(name, value):
    with pytest.raises(ValueError, match=name):
        replace(CONFIG, **{name: value}).check()


def test_the_approach_heading_is_conde_controls_own():
    """arc_end ends a turn at the heading the lane follower steers to: lane_aligned_approach_per_m
    must be conde_control's offset gain over its heading gain (its config/control.yaml and the
    default of ControlConfig), or the hand-over swings the robot again."""
    import os

    from conde_control.control_law import ControlConfig, load_config

    here = os.path.dirname(os.path.abspath(__file__))
    control_yaml = os.path.join(here, "..", "..", "conde_control", "config", "control.yaml")
    for control in (load_config(control_yaml), ControlConfig()):
        assert CONFIG.lane_aligned_approach_per_m == pytest.approx(
            control.offset_gain_per_m2 / control.heading_gain_per_m)
