"""The hand-over from a junction's blind arc to the lane follower (handover.py): the offset reference
starts at the offset measured where the arc ends and eases to 0, instead of a sharp turn toward the
centre that swings the robot's rear onto the outer line (issue 15, D3 Bullet track seed 3)."""

import math
from dataclasses import replace

import pytest

from conde_decision.decision_logic import RIGHT, DecisionLogic
from conde_decision.handover import HandOver
from recorded_sequence import load, replay
from test_arc_end import CONFIG, LAP2, turn_right_logic


def test_the_reference_starts_at_the_offset_and_eases_linearly_to_0():
    handover = HandOver(0.6)
    assert handover.reference(1.0) == (0.0, 0.0)
    handover.start(-0.171, 10.0)
    offset_ref_m, heading_ref_rad = handover.reference(10.0)
    assert offset_ref_m == pytest.approx(-0.171)
    assert heading_ref_rad == pytest.approx(math.atan(0.171 / 0.6))  # toward the centre: left
    assert handover.reference(10.3)[0] == pytest.approx(-0.0855)
    assert handover.reference(10.61) == (0.0, 0.0)
    assert handover.active  # reference() is a query; step() ends the easing
    assert handover.step(True, 0.0, 10.61) == (0.0, 0.0)
    assert not handover.active
    assert handover.step(True, -0.1, 10.1) == (0.0, 0.0)  # once done, done (until the next arc)


def test_zero_ease_turns_it_off_and_bad_values_are_named():
    handover = HandOver(0.0)
    handover.start(0.2, 0.0)
    assert handover.reference(0.0) == (0.0, 0.0)
    with pytest.raises(ValueError, match="handover_ease_m"):
        HandOver(-1.0)
    with pytest.raises(ValueError, match="handover_ease_m"):
        CONFIG.__class__(handover_ease_m=-0.1).check()


def hand_over(config=CONFIG):
    """The recorded lap-2 right turn (D1 track seed 1) through DecisionLogic, the rows after its end
    included; [(t_s, row, out)] from the frame the turn ended on."""
    rows = load(LAP2)
    logic = turn_right_logic()
    logic = DecisionLogic(logic.machine.spec, config)
    logic.on_odometry(rows[0]["yaw_rad"], rows[0]["odom_path_m"])
    logic.on_signal(RIGHT, 1.0)
    outputs = replay(logic, rows)
    end = next(k for k, (_, _, out) in enumerate(outputs) if out.state != "turn_right")
    return outputs[end:]


def test_after_the_arc_the_follower_is_not_asked_for_the_centre_at_once():
    """The turn ends 0.1+ m right of the centre, heading back to it: the reference starts there,
    the heading reference leads toward the centre, and both ease off as the robot drives on."""
    outputs = hand_over()
    _, row, out = outputs[0]
    assert out.transitions == [("turn_right", "lane_aligned", "follow_lane")]
    assert row["lateral_offset_m"] < -0.1
    assert out.lateral_offset_ref_m == pytest.approx(row["lateral_offset_m"], abs=0.01)
    assert out.heading_ref_rad > 0.1
    assert len(outputs) > 1
    refs = [abs(o.lateral_offset_ref_m) for _, _, o in outputs]
    assert all(b <= a + 1e-9 for a, b in zip(refs, refs[1:]))


def test_the_hand_over_off_asks_for_the_centre_at_once():
    outputs = hand_over(replace(CONFIG, handover_ease_m=0.0))
    assert all(o.lateral_offset_ref_m == 0.0 and o.heading_ref_rad == 0.0 for _, _, o in outputs)
