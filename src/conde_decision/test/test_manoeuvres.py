"""A robot's manoeuvre file over the state machine, and the check of every arc against a car's
minimum turning radius (conde_decision/manoeuvres.py), on the real state machine and Major
Alvega's manoeuvre file."""

import math
import os

import pytest

from conde_decision.manoeuvres import (ManoeuvreError, apply_manoeuvres, check_turning_radius, load_manoeuvres,
                                       parse_manoeuvres, tightest_arc)
from conde_decision.parking import bay_entry_lead_m
from conde_decision.state_machine import load_state_machine

HERE = os.path.dirname(os.path.abspath(__file__))
SRC = os.path.dirname(os.path.dirname(HERE))
STATES = os.path.join(SRC, "conde_decision", "config", "conde_states.yaml")
MAJOR_MANOEUVRES = os.path.join(SRC, "conde_major", "config", "major_manoeuvres.yaml")
MAJOR_TURNING_RADIUS_M = 0.445  # its URDF (conde_major test_urdf_geometry checks this number)


@pytest.fixture(scope="module")
def spec():
    return load_state_machine(STATES)


def test_conde_states_are_too_tight_for_major_alvega(spec):
    assert tightest_arc(spec) == ("park_swing_out", 0.4)
    with pytest.raises(ManoeuvreError) as error:
        check_turning_radius(spec, MAJOR_TURNING_RADIUS_M, "its URDF", spec_source="parameter ~state_machine (x)")
    assert str(error.value) == (
        "parameter ~state_machine (x): states.park_swing_out.command.radius_m: 0.400 m is tighter than the robot's "
        "minimum turning radius 0.445 m (its URDF); give the state a radius >= 0.445 m in the robot's manoeuvre file")
    check_turning_radius(spec, 0.0, "turns on the spot")  # Conde: any arc


def test_major_alvega_manoeuvres_fit_its_turning_radius_and_keep_the_s(spec):
    manoeuvres = load_manoeuvres(MAJOR_MANOEUVRES)
    major = apply_manoeuvres(spec, manoeuvres, MAJOR_MANOEUVRES)
    check_turning_radius(major, MAJOR_TURNING_RADIUS_M, "its URDF", manoeuvres, MAJOR_MANOEUVRES)
    assert tightest_arc(major)[1] >= MAJOR_TURNING_RADIUS_M

    def s_shape(s):
        out, back = s.states["park_swing_out"].command, s.states["park_swing_in"].command
        assert (out.branch, back.branch) == ("right", "left") and out.radius_m == back.radius_m
        angle = out.distance_m / out.radius_m
        assert back.distance_m == out.distance_m  # straight again at the end
        return 2 * out.radius_m * (1 - math.cos(angle)), 2 * out.radius_m * math.sin(angle)

    side_conde, ahead_conde = s_shape(spec)
    side_major, ahead_major = s_shape(major)
    assert side_major == pytest.approx(side_conde, abs=1e-3)  # into the middle of the bay as Conde
    # Major's body (centre 0.16 m ahead of its reference point) ends where Conde's (centre 0.197 m
    # behind its own) does: the longer S begins correspondingly earlier.
    start = {n: s.states["park_drive"].command.distance_m + s.states["park_creep"].command.distance_m
             for n, s in (("conde", spec), ("major", major))}
    assert start["major"] + ahead_major + 0.160 == pytest.approx(start["conde"] + ahead_conde - 0.1965, abs=2e-3)
    # nothing else changed: the states, their transitions and the other commands
    assert list(major.states) == list(spec.states) and major.transitions() == spec.transitions()
    changed = [n for n in spec.states if major.states[n].command != spec.states[n].command]
    assert changed == ["park_drive", "park_swing_out", "park_swing_in", "bay_creep", "bay_drive_in"]
    assert spec.states["park_swing_out"].command.radius_m == 0.4  # the spec given is left as it was
    # the bay: the same turn; straight in, Major's body centre ends as deep as Conde's
    turn = major.states["bay_turn_in"].command
    assert turn == spec.states["bay_turn_in"].command and turn.radius_m >= MAJOR_TURNING_RADIUS_M
    depth = {n: s.states["bay_turn_in"].command.radius_m + s.states["bay_drive_in"].command.distance_m
             for n, s in (("conde", spec), ("major", major))}
    assert depth["major"] + 0.160 == pytest.approx(depth["conde"] - 0.1965, abs=2e-3)
    # the way into a bay begins later (the parking uses the spec given to it)
    assert bay_entry_lead_m(spec, "bay_approach") == pytest.approx(0.92)
    assert bay_entry_lead_m(major, "bay_approach") == pytest.approx(0.55)


def test_a_tighter_radius_in_the_manoeuvre_file_names_the_file_and_state(spec):
    manoeuvres = parse_manoeuvres({"park_swing_in": {"radius_m": 0.44}}, "major.yaml")
    major = apply_manoeuvres(spec, manoeuvres, "parameter /conde_decision/manoeuvres (major.yaml)")
    with pytest.raises(ManoeuvreError) as error:
        # park_swing_out (0.4, from the state machine) comes first in the file
        check_turning_radius(major, 0.445, "URDF", manoeuvres, "parameter /conde_decision/manoeuvres (major.yaml)",
                             "states.yaml")
    assert str(error.value).startswith("states.yaml: states.park_swing_out.command.radius_m: 0.400 m")
    manoeuvres["park_swing_out"] = {"radius_m": 0.5}
    major = apply_manoeuvres(spec, manoeuvres, "m")
    with pytest.raises(ManoeuvreError) as error:
        check_turning_radius(major, 0.445, "URDF", manoeuvres, "parameter /conde_decision/manoeuvres (major.yaml)")
    assert str(error.value).startswith("parameter /conde_decision/manoeuvres (major.yaml): park_swing_in.radius_m: "
                                       "0.440 m is tighter than the robot's minimum turning radius 0.445 m (URDF)")


@pytest.mark.parametrize("data, message", [
    ([1], "m.yaml: expected a mapping of state names to {radius_m, distance_m}, got list"),
    ({"park_drive": 1.2}, "m.yaml: park_drive: expected a mapping with radius_m and/or distance_m, got 1.2"),
    ({"park_drive": {"speed": "cruise"}}, "m.yaml: park_drive.speed: unknown field (expected radius_m or distance_m)"),
    ({"park_drive": {"distance_m": 0}}, "m.yaml: park_drive.distance_m: expected a number > 0 [m], got 0"),
    ({"park_drive": {"distance_m": True}}, "m.yaml: park_drive.distance_m: expected a number > 0 [m], got True"),
    ({"park_drive": {"distance_m": float("nan")}}, "m.yaml: park_drive.distance_m: expected a number > 0 [m], got nan"),
])
def test_bad_manoeuvre_files_name_the_field(data, message):
    with pytest.raises(ManoeuvreError) as error:
        parse_manoeuvres(data, "m.yaml")
    assert str(error.value) == message


def test_unknown_state_or_radius_without_an_arc(spec, tmp_path):
    with pytest.raises(ManoeuvreError, match=r"^m: park_swing: no such state in the state machine .*conde_states"):
        apply_manoeuvres(spec, {"park_swing": {"radius_m": 0.5}}, "m")
    with pytest.raises(ManoeuvreError) as error:
        apply_manoeuvres(spec, {"park_drive": {"radius_m": 0.5}}, "m")
    assert str(error.value) == "m: park_drive.radius_m: the state drives no arc (its command has no radius_m)"
    path = tmp_path / "twice.yaml"
    path.write_text("park_drive: {distance_m: 1.0}\npark_drive: {distance_m: 2.0}\n")
    with pytest.raises(ManoeuvreError, match="park_drive"):
        load_manoeuvres(str(path))
    with pytest.raises(ManoeuvreError, match="cannot read the manoeuvre file"):
        load_manoeuvres(str(tmp_path / "none.yaml"))
