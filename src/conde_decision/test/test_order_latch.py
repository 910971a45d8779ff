"""The direction order latched before the crosswalk's stop line by a robot whose panel camera is
ahead of its base_footprint (DecisionConfig.order_latch_lead_m; Major Alvega's top camera is
0.448 m ahead of its rear axle): a misread while the camera is over the crosswalk is ignored, a
read while the robot stands at the line still counts.  The 1-D route model of road_model.py."""

import os
from dataclasses import replace

import pytest

from conde_decision.decision_logic import FORWARD, LEFT, STOP, DecisionConfig, DecisionLogic
from conde_decision.state_machine import load_state_machine
from road_model import HALF_LAP_M, Road

SPEC = load_state_machine(os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "config",
                                       "conde_states.yaml"))
# each order is given once, as one message: it counts at once, driving too (test_order_gate.py: the hold)
CONFIG = replace(DecisionConfig(), junction_fallback_m=0.0, order_hold_s=0.0, order_crosswalk_range_m=0.0)


def make(lead_m):
    return Road(DecisionLogic(SPEC, replace(CONFIG, order_latch_lead_m=lead_m)))


def to_southbound_crossing(road, before_edge_m):
    """After the go, along the north loop until base_footprint is before_edge_m before the near
    edge of the southbound crossing (whose fork opens right)."""
    road.logic.on_signal(FORWARD, 1.0)
    road.drive_m(HALF_LAP_M - before_edge_m - road.s)


@pytest.mark.parametrize("lead_m, fork", [(0.448, "fork_straight"), (0.0, "fork_right")])
def test_a_misread_with_the_panel_camera_over_the_crosswalk(lead_m, fork):
    """"left" (not obeyable at the south fork: straight on), then "forward" misread (D2 with Major
    Alvega: at 0.83 confidence, base_footprint 0.31 m before the stop line): ignored with the lead,
    taken without it ("forward" takes the south fork's branch)."""
    road = make(lead_m)
    to_southbound_crossing(road, 3.0)
    road.logic.on_signal(LEFT, 0.77)
    road.drive_m(HALF_LAP_M - 0.3 - road.s)
    road.logic.on_signal(FORWARD, 0.83)
    assert bool(road.logic.notes) == (lead_m > 0)
    events = road.until(fork).events
    assert [e for e in events if e.startswith("fork_")] == [fork]


def test_an_order_read_standing_at_the_line_counts_with_the_lead():
    """Stopped before the crosswalk (base_footprint stop_margin_m before it, the camera past it):
    the order that sends the robot on counts; misreads once it drives on do not."""
    road = make(0.448)
    to_southbound_crossing(road, 3.0)
    road.logic.on_signal(STOP, 1.0)
    road.until("crosswalk_reached")
    road.run(2.0)  # braking to a stand
    road.stand_still_at(1.0)
    road.logic.on_signal(LEFT, 1.0)
    assert road.logic.state == "follow_lane" and not road.logic.notes
    road.drive_m(0.05)
    road.logic.on_signal(FORWARD, 0.83)
    assert road.logic.notes
    events = road.until("fork_straight").events
    assert [e for e in events if e.startswith("fork_")] == ["fork_straight"]
