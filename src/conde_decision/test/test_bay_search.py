"""Bay parking on what the cameras see (parking_place auto): what counts as a line of the
bay-parking area, when the search gives up for the parallel bay, and how box sightings are
grouped (review findings of the parking work)."""
import os
from dataclasses import replace

import pytest

from conde_decision.decision_logic import PARKING, DecisionConfig, DecisionLogic
from conde_decision.parking import BayFinder
from conde_decision.state_machine import load_state_machine
from road_model import DT_S, Road

PACKAGE_DIR = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SPEC = load_state_machine(os.path.join(PACKAGE_DIR, "config", "conde_states.yaml"))
# each order is given once, as one message: it counts at once, driving too (test_order_gate.py: the hold)
CONFIG = replace(DecisionConfig(), junction_fallback_m=0.0, order_hold_s=0.0, order_crosswalk_range_m=0.0)
BAY_M = 0.773
STEP_M = CONFIG.cruise_speed_mps * DT_S


def make(**config):
    return Road(DecisionLogic(SPEC, replace(CONFIG, **config)))


def order_parking(road):
    road.run(10 * DT_S)
    road.logic.on_signal(PARKING, 1.0)
    notes = []
    step = road.step

    def step_and_keep_notes():
        out = step()
        notes.extend(road.logic.notes)
        return out
    road.step = step_and_keep_notes
    return notes


def test_one_unconfirmed_line_sighting_does_not_turn_the_parallel_fallback_off():
    road = make()
    notes = order_parking(road)
    road.bay_lines_s = [0.9]  # seen in one frame only (a glint, the painted "P" ...)
    road.step()
    road.bay_lines_s = []
    out = road.until("parking_parallel")
    assert out.transitions == [("go_to_parking", "parking_parallel", "park_drive")]
    assert road.s == pytest.approx(CONFIG.parking_search_m, abs=3 * STEP_M)
    assert road.logic.bays.lines_m == [] and not notes


def test_lines_that_never_pair_into_a_bay_give_up_past_the_last_one_for_the_parallel_bay():
    road = make()
    notes = order_parking(road)
    road.bay_lines_s = [1.0, 1.0 + 0.45]  # known lines, but no bay width apart
    out = road.until("parking_parallel")
    assert out.transitions == [("go_to_parking", "parking_parallel", "park_drive")]
    assert road.s == pytest.approx(1.45 + CONFIG.bay_search_past_m, abs=3 * STEP_M)
    assert any("enclose no free bay" in n for n in notes)


def test_bays_all_occupied_give_up_in_bay_approach_for_the_parallel_bay():
    road = make()
    notes = order_parking(road)
    road.bay_lines_s = [1.5, 1.5 + BAY_M, 1.5 + 2 * BAY_M]
    road.bay_boxes_s = [1.5 + 0.09, 1.5 + BAY_M + 0.09]  # a box in each bay
    road.until("parking_bays_seen")
    assert road.logic.state == "bay_approach"
    out = road.until("parking_parallel")
    assert out.transitions == [("bay_approach", "parking_parallel", "park_drive")]
    assert road.s == pytest.approx(1.5 + 2 * BAY_M + CONFIG.bay_search_past_m, abs=3 * STEP_M)
    assert any("enclose no free bay" in n for n in notes)


def test_a_box_passed_by_is_one_box_at_its_nearest_sighting():
    """While the robot passes a box its near face leaves the view: the nearest point seen moves on
    along the box.  Those sightings are the same box, which stays where its near end was seen."""
    finder = BayFinder()
    finder.on_lines(0.0, [1.0, 1.0 + BAY_M, 1.0 + 2 * BAY_M])
    finder.on_lines(0.1, [0.9, 0.9 + BAY_M, 0.9 + 2 * BAY_M])
    box_m = 1.0 + 0.09  # in the south bay
    for k in range(17):  # driven on 0.1 m per frame; the view begins 0.19 m behind base_footprint
        t = 0.1 * k
        finder.on_box(t, max(box_m - t, -0.19), -0.6)
    assert finder.boxes_m == [pytest.approx(box_m)]
    assert [b[2] for b in finder.bays()] == [True, False]
    assert finder.free_bay() == pytest.approx((1.0 + BAY_M, 1.0 + 2 * BAY_M))


def test_a_box_seen_once_is_not_known():
    finder = BayFinder()
    finder.on_box(0.0, 1.2, -0.6)
    assert finder.boxes_m == []
    finder.on_box(0.1, 1.1, -0.6)
    assert finder.boxes_m == [pytest.approx(1.2)]
