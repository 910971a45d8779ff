"""Orders while driving (order_gate.py, DecisionConfig.order_hold_s): a far read of the panel that
flickers to another signal for a few frames is no order; a change that stays is, and standing
every signal counts at once.  The 1-D route model of road_model.py, one panel message per camera
frame as conde_semaphore publishes them."""

import os
from dataclasses import replace

import pytest

from conde_decision.decision_logic import (END_OF_TRIAL, FORWARD, LEFT, NONE, RIGHT, STOP, DecisionConfig,
                                           DecisionLogic)
from conde_decision.order_gate import OrderGate
from conde_decision.state_machine import load_state_machine
from road_model import DT_S, HALF_LAP_M, VIEW_M, Road

SPEC = load_state_machine(os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "config",
                                       "conde_states.yaml"))
CONFIG = replace(DecisionConfig(), junction_fallback_m=0.0)


def make(**config):
    return Road(DecisionLogic(SPEC, replace(CONFIG, **config)))


def show(road, signal, confidence, seconds):
    """The panel read as `signal` in every camera frame for `seconds`: one message, then one lane step
    (stamped like the frame); returns the transitions the signals fired."""
    fired = []
    for _ in range(max(1, int(round(seconds / DT_S)))):
        fired += road.logic.on_signal(signal, confidence, road.t)
        road.step()
    return fired


# --- OrderGate -------------------------------------------------------------------------------------

def test_standing_every_signal_counts_at_once():
    gate = OrderGate(1.5)
    assert gate.accept("forward", 10.0, standing=True)
    assert gate.accept("left", 10.1, standing=True) and gate.held == "left"


def test_driving_a_change_counts_after_the_hold():
    gate = OrderGate(1.5)
    gate.accept("forward", 0.0, standing=True)
    assert gate.accept("forward", 5.0, standing=False)  # the order held: at once
    assert not gate.accept("right", 5.0, standing=False)
    assert not gate.accept("right", 6.49, standing=False)
    assert gate.held == "forward"
    assert gate.accept("right", 6.5, standing=False) and gate.held == "right"


def test_another_signal_restarts_the_hold():
    gate = OrderGate(1.0)
    gate.accept("forward", 0.0, standing=True)
    assert not gate.accept("right", 1.0, standing=False)
    assert not gate.accept("right", 1.9, standing=False)
    assert not gate.accept("left", 1.95, standing=False)
    assert not gate.accept("right", 2.0, standing=False)
    assert not gate.accept("right", 2.9, standing=False)
    assert gate.accept("right", 3.0, standing=False)


def test_the_held_order_read_again_restarts_the_hold():
    gate = OrderGate(1.0)
    gate.accept("forward", 0.0, standing=True)
    assert not gate.accept("right", 1.0, standing=False)
    assert gate.accept("forward", 1.5, standing=False)
    assert not gate.accept("right", 1.6, standing=False)
    assert not gate.accept("right", 2.5, standing=False)


def test_none_pauses_the_count():
    """Major Alvega's D1: end_of_trial read from afar in runs of 0.2-1.4 s with frames of none between."""
    gate = OrderGate(1.5)
    gate.accept("forward", 0.0, standing=True)
    assert not gate.accept("end_of_trial", 158.267, standing=False)
    assert not gate.accept("end_of_trial", 158.4, standing=False)  # 0.133 s read
    gate.pause()  # none from 158.433 to 158.533: not counted
    assert not gate.accept("end_of_trial", 158.533, standing=False)
    assert not gate.accept("end_of_trial", 159.8, standing=False)  # 0.133 + 1.267 = 1.4 s read
    assert gate.accept("end_of_trial", 159.9, standing=False)  # 1.5 s read


def test_a_pause_longer_than_the_hold_restarts_it():
    """D3: left read 0.1 s, none for 1.77 s, left again: two flickers, not one order."""
    gate = OrderGate(1.5)
    gate.accept("forward", 0.0, standing=True)
    assert not gate.accept("left", 27.633, standing=False)
    assert not gate.accept("left", 27.7, standing=False)
    gate.pause()
    assert not gate.accept("left", 29.5, standing=False)
    assert not gate.accept("left", 30.95, standing=False)
    assert gate.accept("left", 31.0, standing=False)


def test_a_zero_hold_takes_every_signal():
    gate = OrderGate(0.0)
    gate.accept("forward", 0.0, standing=True)
    assert gate.accept("right", 1.0, standing=False)


@pytest.mark.parametrize("hold", [-0.1, float("nan"), "1", True, None])
def test_a_bad_hold_is_refused(hold):
    with pytest.raises(ValueError, match="hold_s"):
        OrderGate(hold)


def test_a_bad_order_hold_is_refused_naming_the_field():
    with pytest.raises(ValueError, match="order_hold_s"):
        DecisionConfig(order_hold_s=-1.0).check()


# --- the decision ----------------------------------------------------------------------------------

def to_finish_approach(road):
    """Go, then along the road until end_of_trial is read while driving, 5 m before a crossing."""
    assert show(road, FORWARD, 1.0, DT_S) == [("wait_for_go", "signal_forward", "follow_lane")]
    road.drive_m(HALF_LAP_M - 5.0 - road.s)
    assert show(road, END_OF_TRIAL, 1.0, 2.0)[:1] == [("follow_lane", "signal_end_of_trial", "approach_finish")]


FLIPS_BEFORE = [("approach_finish", "signal_right", "follow_lane"),
                ("follow_lane", "signal_end_of_trial", "approach_finish")]


@pytest.mark.parametrize("hold_s, flips", [(1.5, []), (0.0, FLIPS_BEFORE)])
def test_the_recorded_far_read_does_not_cancel_the_finish(hold_s, flips):
    """D3 (ODE, nominal, CI): end_of_trial 1.00, then right 0.57 for 0.17 s, then end_of_trial again,
    while the robot drives to the crosswalk to stop: approach_finish stays (with the hold; without it,
    as before, the robot went to follow_lane and back)."""
    road = make(order_hold_s=hold_s, order_crosswalk_range_m=0.0)  # the hold alone: read from 5 m
    to_finish_approach(road)
    fired = show(road, RIGHT, 0.57, 0.17) + show(road, END_OF_TRIAL, 1.0, 1.0)
    assert fired == flips
    assert road.logic.state == "approach_finish"
    road.until("crosswalk_reached")
    assert road.logic.state == "finished"


def test_the_flicker_seen_approaching_the_panel_leaves_the_order():
    """D3's approach to a crossing (31.9-36.1 s): right / left / forward alternating every 0.1-0.5 s with
    none between: the order stays forward, no direction reaches the fork."""
    road = make()
    show(road, FORWARD, 1.0, DT_S)
    road.drive_m(HALF_LAP_M - 6.0 - road.s)
    for signal, confidence, seconds in [(RIGHT, 0.54, 0.43), (LEFT, 0.93, 0.23), (FORWARD, 0.93, 0.2),
                                        (RIGHT, 0.93, 0.13), (NONE, 1.0, 0.3), (RIGHT, 0.83, 0.47),
                                        (FORWARD, 0.91, 0.3), (RIGHT, 0.91, 0.1), (LEFT, 0.69, 0.37)]:
        assert show(road, signal, confidence, seconds) == []
    assert road.logic.last_signal == FORWARD and road.logic.orders.held == FORWARD
    assert next_fork(road) == "fork_right"  # "forward" takes the 2nd fork's branch (it opens right)


def next_fork(road):
    for _ in range(int(60.0 / DT_S)):
        forks = [e for e in road.step().events if e.startswith("fork_")]
        if forks:
            return forks[0]
    raise AssertionError("no fork within 60 s")


def test_a_change_that_stays_is_taken_after_the_hold():
    """D2: the panel turns from forward to left while the robot drives (read from 41.2 s for 6 s): the
    order is taken order_hold_s after the first read, and it chooses the next fork."""
    road = make(order_hold_s=1.5, order_crosswalk_range_m=0.0)  # the hold alone: read from 5 m
    show(road, FORWARD, 1.0, DT_S)
    road.drive_m(HALF_LAP_M - 5.0 - road.s)
    first_s = road.t
    while road.logic.last_signal != LEFT:  # follow_lane takes no transition on a direction
        assert road.t - first_s < 1.5 + 2 * DT_S, "left not taken within the hold"
        assert show(road, LEFT, 1.0, DT_S) == []
    taken_s = road.t - DT_S  # the stamp of the message that was taken
    assert taken_s - first_s >= 1.5 - 1e-9
    assert road.logic.last_signal == LEFT and road.logic.state == "follow_lane"
    assert next_fork(road) == "fork_straight"  # the 2nd fork opens right: "left" goes straight on


# --- the panel is over the crosswalk (DecisionConfig.order_crosswalk_range_m) ------------------------

def test_driving_a_change_away_from_the_panel_is_watched_not_taken():
    gate = OrderGate(1.5)
    gate.accept("forward", 0.0, standing=True)
    for frame in range(71):  # read 7 s, one message per 0.1 s: still not taken
        assert not gate.accept("stop", 5.0 + 0.1 * frame, standing=False, panel_ahead=False)
    assert gate.held == "forward" and gate.read_s == pytest.approx(7.0)
    assert gate.accept("stop", 12.1, standing=False, panel_ahead=True) and gate.held == "stop"


def test_standing_and_the_order_held_need_no_panel_ahead():
    gate = OrderGate(1.5)
    assert gate.accept("forward", 0.0, standing=True, panel_ahead=False)
    assert gate.accept("forward", 3.0, standing=False, panel_ahead=False)
    assert gate.accept("stop", 3.1, standing=True, panel_ahead=False)


#: V1 (ODE, nominal track, competition run before this gate; the panel showed forward from 3 s to the
#: end): the red triangles of the danger signs beside the road read as stop by conde_semaphore while
#: driving, as (distance driven past the last crosswalk's near edge at the first read [m], how long
#: it was read [s]): 6.767-14.233 s, 16.333-22.2 s, 25.067-31.233 s (north loop, lap 1),
#: 57.033-62.967 s (south loop).  Each made the robot go to approach_stop.
V1_STOP_READS = [(0.0, 1.67, 7.47), (0.0, 6.49, 5.87), (0.0, 10.85, 6.17), (HALF_LAP_M, 5.40, 5.93)]


@pytest.mark.parametrize("range_m, first_fired", [
    (2.0, []), (0.0, [("follow_lane", "signal_stop", "approach_stop")])])
def test_v1_danger_signs_read_as_stop_are_no_order(range_m, first_fired):
    """With the crosswalk out of sight these reads are no order (the old rule, range 0, took each one)."""
    road = make(order_crosswalk_range_m=range_m)
    show(road, FORWARD, 1.0, DT_S)
    for crossing_s, past_m, seconds in V1_STOP_READS:
        road.drive_m(crossing_s + past_m - road.s)
        fired = show(road, STOP, 1.0, seconds)
        show(road, NONE, 1.0, 2.0)
        if range_m == 0.0:
            assert fired[:1] == first_fired
            return
        assert fired == []
        assert road.logic.state == "follow_lane" and road.logic.orders.held == FORWARD
    assert road.logic.last_signal == FORWARD


def test_the_panels_stop_read_from_afar_is_taken_with_the_crosswalk_in_sight():
    """D2: the panel turns to stop while the robot drives to the crosswalk and is read from 5 m on:
    the order is taken once conde_tracking sees the crosswalk ahead, and the robot stands before it."""
    road = make(order_hold_s=1.5)
    show(road, FORWARD, 1.0, DT_S)
    road.drive_m(HALF_LAP_M - 5.0 - road.s)
    fired = []
    while not fired:
        assert road.s < HALF_LAP_M, "stop not taken before the crosswalk"
        assert not road.logic.panel_ahead() or road.logic.crosswalk.to_near_edge_m <= 2.0
        fired = show(road, STOP, 1.0, DT_S)
    assert fired == [("follow_lane", "signal_stop", "approach_stop")]
    assert road.logic.panel_ahead() and HALF_LAP_M - road.s <= VIEW_M[1] + 1e-9
    assert road.until("crosswalk_reached").state == "stopped"
    assert road.s < HALF_LAP_M  # stands before the near edge


def test_a_bad_crosswalk_range_is_refused_naming_the_field():
    with pytest.raises(ValueError, match="order_crosswalk_range_m"):
        DecisionConfig(order_crosswalk_range_m=-1.0).check()


# --- a stop at the line (DecisionConfig.stop_near_m) -----------------------------------------------

@pytest.mark.parametrize("stop_near_m", [1.0, 0.0])
def test_a_stop_shown_just_before_the_crosswalk_is_taken_before_the_line(stop_near_m):
    """D2, track seed 9 (both engines): the panel turned to stop when the robot was 0.4 m before the
    crosswalk's near edge and was read for 2.2 s. With the hold alone (stop_near_m 0, as before) it
    was taken on the crosswalk and the robot crossed it under stop (a penalty); taken at once, the
    robot stands before the near edge."""
    road = make(order_hold_s=1.5, stop_near_m=stop_near_m)
    show(road, FORWARD, 1.0, DT_S)
    road.drive_m(HALF_LAP_M - 0.4 - road.s)
    assert road.logic.stop_near() == (stop_near_m > 0.0)
    fired = show(road, STOP, 1.0, DT_S)
    if stop_near_m == 0.0:
        assert fired == []
        fired = show(road, STOP, 1.0, 1.5)
        assert fired == [("follow_lane", "signal_stop", "approach_stop")]
        assert road.s > HALF_LAP_M  # on the crosswalk when it is taken: drives on
        return
    assert fired == [("follow_lane", "signal_stop", "approach_stop")]
    assert road.until("crosswalk_reached").state == "stopped"
    assert HALF_LAP_M - 0.15 <= road.s < HALF_LAP_M  # stands before the near edge


def test_a_stop_taken_at_once_says_how_far_the_line_was():
    road = make(order_hold_s=1.5)
    show(road, FORWARD, 1.0, DT_S)
    road.drive_m(HALF_LAP_M - 0.4 - road.s)
    assert road.logic.on_signal(STOP, 0.9, road.t) == [("follow_lane", "signal_stop", "approach_stop")]
    assert road.logic.notes == ["signal stop (confidence 0.90) while driving taken at once: the crosswalk's near "
                                "edge is %.2f m ahead (stop_near_m 1.00)" % road.logic.crosswalk.to_near_edge_m]
    assert 0.35 < road.logic.crosswalk.to_near_edge_m < 0.45
    road.step()
    assert road.logic.on_signal(STOP, 0.9, road.t) == [] and road.logic.notes == []  # held: no new note


def test_a_stop_read_before_the_near_range_is_held_until_it():
    """stop_near_m only shortens a stop read close to the line: read from 1.15 m on, the stop waits
    (the hold) until the robot is within 1.0 m of the near edge and is taken there."""
    road = make(order_hold_s=1.5)
    show(road, FORWARD, 1.0, DT_S)
    road.drive_m(HALF_LAP_M - 1.15 - road.s)  # the crosswalk in sight, 1.15 m ahead
    assert road.logic.panel_ahead() and not road.logic.stop_near()
    fired = []
    while not fired:
        assert road.logic.crosswalk.to_near_edge_m > 1.0 - 0.5 * DT_S, "taken before the near range"
        fired = show(road, STOP, 1.0, DT_S)
    assert fired == [("follow_lane", "signal_stop", "approach_stop")]
    assert road.logic.crosswalk.to_near_edge_m <= 1.0
    assert road.until("crosswalk_reached").state == "stopped"


def test_a_direction_read_at_the_line_keeps_the_hold():
    road = make(order_hold_s=1.5)
    show(road, FORWARD, 1.0, DT_S)
    road.drive_m(HALF_LAP_M - 0.5 - road.s)
    assert road.logic.stop_near()
    assert show(road, RIGHT, 1.0, 0.5) == [] and road.logic.orders.held == FORWARD


def test_a_bad_stop_near_distance_is_refused_naming_the_field():
    with pytest.raises(ValueError, match="stop_near_m"):
        DecisionConfig(stop_near_m=-0.5).check()
