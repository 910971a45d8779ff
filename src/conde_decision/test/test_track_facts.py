"""The decision node's knowledge of the competition track is pinned to the generated track
description (worlds/tracks/competition_track.geometry.yaml, written by conde_worlds'
generate_track): if the track is drawn again with other measures, these tests name every number
of the decision's configuration and state machine that must follow."""
import math
import os

import pytest
import yaml

from conde_decision.decision_logic import DecisionConfig
from conde_decision.state_machine import load_state_machine

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.normpath(os.path.join(HERE, "..", "..", ".."))
GEOMETRY = os.path.join(REPO, "worlds", "tracks", "competition_track.geometry.yaml")
STATES = os.path.join(HERE, "..", "config", "conde_states.yaml")


@pytest.fixture(scope="module")
def track():
    with open(GEOMETRY) as f:
        return yaml.safe_load(f)


def road(track, name):
    return next(r["reference"] for r in track["roads"] if r["name"] == name)


def test_crosswalk_length(track):
    near_y, far_y = track["crosswalk"]["box"]["y_m"]
    assert DecisionConfig().crosswalk_length_m == pytest.approx(far_y - near_y, abs=1e-3)


def test_fork_distance_from_the_crosswalk(track):
    d = track["dimensions"]
    near_y, far_y = track["crosswalk"]["box"]["y_m"]
    northbound = d["fork_y_m"] - far_y    # far edge of the crosswalk to the north fork
    southbound = near_y + d["fork_y_m"]   # driving south, the near edge is the far one
    # One distance serves both forks (1.82 and 1.73 m): the junction's turn is 2 m of lane wide.
    assert abs(DecisionConfig().fork_distance_m - northbound) < 0.1
    assert abs(DecisionConfig().fork_distance_m - southbound) < 0.1


def test_loops(track):
    d = track["dimensions"]
    config = DecisionConfig()
    # The lane on the outside of the north loop (counter-clockwise), the inside of the south one.
    assert config.loop_lane_radii_m == pytest.approx((d["loop_radius_m"] + d["lane_offset_m"],
                                                      d["loop_radius_m"] - d["lane_offset_m"]), abs=1e-4)
    arc, line, _ = road(track, "north_loop")
    assert config.loop_sweep_rad == pytest.approx(abs(arc["sweep_rad"]), abs=1e-5)
    assert config.loop_exit_m == pytest.approx(math.dist(line["from"], line["to"]), abs=1e-4)


def test_junction_turn_radii_of_the_state_machine(track):
    d = track["dimensions"]
    spec = load_state_machine(STATES)
    radii = {name: state.command.radius_m for name, state in spec.states.items()
             if state.command.radius_m and name.startswith("turn_")}  # (not the parking manoeuvres)
    assert radii == {"turn_left": pytest.approx(d["fork_radius_m"] + d["lane_offset_m"], abs=1e-4),
                     "turn_right": pytest.approx(d["fork_radius_m"] - d["lane_offset_m"], abs=1e-4)}
