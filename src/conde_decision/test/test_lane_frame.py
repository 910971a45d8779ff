"""The lane the tracker measured and the own lane's frame (lane_frame.py): the lane index joined
with the modulo of the line spacing; on a recorded D2 sequence through DecisionLogic."""
import math
import os

import pytest

from conde_decision.decision_logic import DecisionConfig, DecisionLogic
from conde_decision.lane_frame import lane_frame
from conde_decision.state_machine import load_state_machine
from recorded_sequence import load, replay

SPEC = load_state_machine(os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "config",
                                       "conde_states.yaml"))
LINE_SPACING_M = DecisionConfig().line_spacing_m  # 0.8065: the config's, for the modulo
MEASURED_M = 0.782  # the spacing conde_tracking measures on the competition track


def test_index_0_is_the_own_lane():
    frame = lane_frame(0.03, 0, MEASURED_M, True, LINE_SPACING_M)
    assert (frame.own_offset_m, frame.lanes_left, frame.source) == (0.03, 0, "index")


def test_index_1_adds_the_measured_spacing_not_the_configs():
    frame = lane_frame(-MEASURED_M + 0.03, 1, MEASURED_M, True, LINE_SPACING_M)
    assert frame.own_offset_m == pytest.approx(0.03) and frame.lanes_left == 1 and frame.source == "index"
    assert frame.shift_m == pytest.approx(MEASURED_M)
    # the modulo alone was 2.5 cm off there
    assert lane_frame(-MEASURED_M + 0.03, -1, MEASURED_M, True, LINE_SPACING_M).own_offset_m == \
        pytest.approx(0.03 + LINE_SPACING_M - MEASURED_M)
    # no spacing measured: the config's
    assert lane_frame(-0.8, 1, math.nan, True, LINE_SPACING_M).own_offset_m == pytest.approx(-0.8 + LINE_SPACING_M)


def test_unknown_index_takes_the_nearest_lane():
    frame = lane_frame(-0.79, -1, MEASURED_M, True, LINE_SPACING_M)
    assert frame.own_offset_m == pytest.approx(-0.79 + LINE_SPACING_M)
    assert (frame.lanes_left, frame.source) == (1, "modulo")
    assert lane_frame(0.1, -1, MEASURED_M, True, LINE_SPACING_M).own_offset_m == pytest.approx(0.1)


@pytest.mark.parametrize("lateral_m, index", [(-0.809, 0), (0.143, 1)])
def test_an_index_naming_another_lane_than_the_nearest_is_not_used(lateral_m, index):
    """Recorded at D2's north fork (lap 2): the index flips while the offset stays against one lane."""
    frame = lane_frame(lateral_m, index, MEASURED_M, True, LINE_SPACING_M)
    assert frame.source == "modulo" and abs(frame.own_offset_m) < 0.15


def test_outside_the_doubt_the_tracker_is_used_as_it_is():
    for index in (-1, 0, 1):
        frame = lane_frame(-0.78, index, MEASURED_M, False, LINE_SPACING_M)
        assert (frame.own_offset_m, frame.lanes_left, frame.source) == (-0.78, 0, "tracker")
    assert math.isnan(lane_frame(math.nan, 1, MEASURED_M, True, LINE_SPACING_M).own_offset_m)


def test_recorded_d2_lap2_north_fork_keeps_the_offset_on_the_own_lane():
    """D2 on ODE, lap 2, from the stop at the crosswalk through the north fork (order "right":
    straight on), conde_tracking still on the lane on the left since lap 1's south fork crossing.
    Its index flips at the fork (0 with -0.81 m, 1 with +0.14 m); taken as given the offset jumped by
    a lane's width both ways and the robot turned round there (a line touch at 93.1 s).  Joined with
    the nearest lane the offset the control gets stays within the lane."""
    rows = load("d2_lap2_north_fork_sequence.csv")
    lanes = [r for r in rows if r["kind"] == "lane" and r["lane_index"] in (0, 1)]
    as_given = [r["lateral_offset_m"] + r["lane_index"] * r["lane_spacing_m"] for r in lanes]
    assert max(as_given) - min(as_given) > 1.5 * MEASURED_M  # the recorded flips
    logic = DecisionLogic(SPEC, DecisionConfig())
    logic.forks.tracked_lane_unsure = True  # as after lap 1's south fork, crossed straight
    outputs = replay(logic, rows)
    assert ("stopped" not in [o.state for _, _, o in outputs]) and outputs[-1][2].state == "follow_lane"
    assert any("fork_straight" in o.events for _, _, o in outputs)
    used = [o.lateral_offset_m for _, r, o in outputs if r["confidence"] >= logic.config.min_lane_confidence]
    assert max(abs(x) for x in used) < 0.45
    # on the approach (both lines, index 1): the measured spacing, not the config's
    t, row, out = outputs[30]
    assert row["lane_index"] == 1 and out.lateral_offset_m == pytest.approx(row["lateral_offset_m"]
                                                                            + row["lane_spacing_m"])
