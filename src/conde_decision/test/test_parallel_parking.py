"""Parallel parking anchored on what the cameras see (conde_decision.parking.ParallelGapFinder and
the park_entry_near event), and the parking-area search flag of the decision."""
import math
import os
from dataclasses import replace

import pytest

from conde_decision.decision_logic import FORWARD, PARKING, DecisionConfig, DecisionLogic
from conde_decision.parking import ParallelGapFinder, manoeuvre_advance_m
from conde_decision.state_machine import load_state_machine
from road_model import DT_S, Road
from test_decision_logic import drive_to_parked, with_parallel_bay

PACKAGE_DIR = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SPEC = load_state_machine(os.path.join(PACKAGE_DIR, "config", "conde_states.yaml"))
# each order is given once, as one message: it counts at once, driving too (test_order_gate.py: the hold)
CONFIG = replace(DecisionConfig(), junction_fallback_m=0.0, order_hold_s=0.0, order_crosswalk_range_m=0.0)
STEP_M = CONFIG.cruise_speed_mps * DT_S
# The nominal track from the P start pose (base_footprint 0.33 m before y = 0), along the road:
BAY_START_M = 1.551  # the parallel bay's straight part begins (y 1.221)
P2_BOXES_M = ((1.8825, 2.4825), (3.6825, 4.2825))  # P2's boxes (near, far): a 1.2 m gap between them
P2_GAP_CENTRE_M = 3.0825
# The S into the bay: park_creep's straight, then two 0.4 m arcs of 92.2 deg, right then left.
S_ADVANCE_M = 0.43 + 2 * 0.4 * math.sin(0.6437 / 0.4)


def make(**config):
    return Road(DecisionLogic(SPEC, replace(CONFIG, **config)))


def event_positions(road, event):
    return [s for s, o in zip(road.positions, road.outputs) if event in [t[1] for t in o.transitions]]


def test_the_manoeuvre_advance_is_the_straight_and_the_s_of_the_states_it_leads_to():
    assert manoeuvre_advance_m(SPEC, "park_creep") == pytest.approx(S_ADVANCE_M, abs=1e-4)
    assert manoeuvre_advance_m(SPEC, "bay_creep") == pytest.approx(0.42 + 0.5, abs=1e-4)  # then 0.931 m sideways
    assert manoeuvre_advance_m(SPEC, "follow_lane") == 0.0  # no distance: ends at once
    assert manoeuvre_advance_m(SPEC, "park_drive") is None  # cruise: not a manoeuvre


def test_the_gap_between_two_boxes_is_its_middle_once_both_are_known():
    finder = ParallelGapFinder(min_gap_m=0.9, bay_centre_m=1.53)
    finder.on_bay_start(0.0, 1.55)
    finder.on_box(0.0, 1.88, 2.46, -0.56)  # the near box; its far end seen
    assert finder.target_m() is None  # one sighting each: nothing known yet
    finder.on_bay_start(0.1, 1.46)
    finder.on_box(0.1, 1.79, 2.39, -0.55)
    assert finder.bay_start_m == pytest.approx(1.555) and finder.boxes() == [(1.88, pytest.approx(2.475))]
    # bay start to the near box: 0.33 m, too short; beyond the box the far end is unknown
    assert finder.target_m() is None
    for t in (0.2, 0.3):
        finder.on_box(t, 3.68 - t, 4.3 - t, -0.55)  # the far box
    finder.on_box(0.3, 2.0, 2.2, -0.2)  # a box on the road: not in the bay
    assert finder.target_m() == pytest.approx(0.5 * (2.475 + 3.68))


def test_the_near_end_of_a_box_passed_by_stays_its_nearest_sighting():
    finder = ParallelGapFinder()
    for t, near in ((0.0, 1.0), (0.5, 0.5), (1.0, 0.0), (1.2, -0.15), (1.5, -0.19)):  # near face out of view
        finder.on_box(t, near, 1.6 - t, -0.55)
    assert finder.boxes() == [(pytest.approx(1.0), pytest.approx(1.6))]


def test_an_empty_bay_is_parked_in_its_middle_from_its_start_and_a_box_without_far_end_is_no_gap():
    finder = ParallelGapFinder(bay_centre_m=1.53)
    finder.on_bay_start(0.0, 1.0)
    finder.on_bay_start(0.2, 0.8)
    assert finder.target_m() == pytest.approx(2.53)
    finder.on_box(0.2, 1.0, float("nan"), -0.6)
    finder.on_box(0.3, 0.9, float("nan"), -0.6)  # 0.2 m into the bay: too short before it, far end unknown
    assert finder.target_m() is None


@pytest.mark.parametrize("shift_m", [0.0, 0.25, -0.15])
def test_p2_the_manoeuvre_begins_from_the_gap_seen_between_the_boxes(shift_m):
    """The S ends with base_footprint park_axle_past_centre_m past the gap's middle, wherever the
    bay and its boxes are along the road (a track drawn a few per cent larger moves them)."""
    boxes = [(a + shift_m, b + shift_m) for a, b in P2_BOXES_M]
    road = with_parallel_bay(make(), BAY_START_M + shift_m, boxes)
    signal_parking(road)
    drive_to_parked(road)
    entry_m = P2_GAP_CENTRE_M + shift_m + CONFIG.park_axle_past_centre_m - S_ADVANCE_M
    assert event_positions(road, "park_entry_near") == [pytest.approx(entry_m, abs=STEP_M + 1e-6)]
    assert entry_m == pytest.approx(2.1 + shift_m, abs=0.01)  # 2.1 m: the stored distance on the nominal track
    assert not fallback_noted(road)


def test_p1_the_manoeuvre_begins_from_the_bays_start_seen():
    road = with_parallel_bay(make(), BAY_START_M + 0.1, boxes=())
    signal_parking(road)
    drive_to_parked(road)
    entry_m = BAY_START_M + 0.1 + CONFIG.park_bay_centre_m + CONFIG.park_axle_past_centre_m - S_ADVANCE_M
    assert event_positions(road, "park_entry_near") == [pytest.approx(entry_m, abs=STEP_M + 1e-6)]
    assert not fallback_noted(road)


def test_without_the_bay_seen_the_stored_distance_is_the_fallback_and_noted():
    road = make()
    signal_parking(road)
    drive_to_parked(road)
    assert event_positions(road, "park_entry_near") == []
    fallback_m = CONFIG.parking_search_m + SPEC.states["park_drive"].command.distance_m
    assert event_positions(road, "distance_elapsed")[0] == pytest.approx(fallback_m, abs=STEP_M + 1e-6)
    assert fallback_noted(road)


def test_the_parking_search_flag_is_set_while_a_state_looks_for_a_parking_place():
    road = with_parallel_bay(make())
    assert not road.logic.parking_search  # wait_for_go
    road.logic.on_signal(FORWARD, 1.0)
    assert road.logic.state == "follow_lane" and not road.logic.parking_search
    road.logic.on_signal(PARKING, 1.0)  # while driving: on to the end of the lap first, no search yet
    assert road.logic.state == "drive_to_parking" and not road.logic.parking_search
    road = with_parallel_bay(make())
    road.logic.on_signal(PARKING, 1.0)  # standing at the start (P challenges): the search begins
    assert road.logic.state == "go_to_parking" and road.logic.parking_search
    road.until("parking_parallel")
    assert road.logic.state == "park_drive" and road.logic.parking_search
    road.until("park_entry_near")
    assert road.logic.state == "park_creep" and not road.logic.parking_search
    for state in ("bay_approach", "go_to_parking", "park_drive"):
        assert any(e in SPEC.states[state].transitions
                   for e in ("parking_bays_seen", "parking_parallel", "bay_entry_near", "park_entry_near"))


def test_sightings_are_taken_only_while_searching():
    """A box beside the road before the parking order is not put along the road."""
    road = with_parallel_bay(make())
    road.logic.on_signal(FORWARD, 1.0)
    road.drive_m(0.5)
    assert road.logic.gap.boxes() == [] and road.logic.gap.bay_start_m is None


_NOTES = {}


def signal_parking(road):
    road.run(100 * DT_S)
    road.logic.on_signal(PARKING, 1.0)
    # keep every step's notes (DecisionLogic.notes holds the last step's)
    step = road.step

    def step_and_keep_notes():
        out = step()
        _NOTES.setdefault(id(road), []).extend(road.logic.notes)
        return out
    road.step = step_and_keep_notes


def fallback_noted(road):
    return any(n.startswith("parallel parking: no free stretch") for n in _NOTES.get(id(road), []))
