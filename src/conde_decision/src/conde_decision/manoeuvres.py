"""A robot's own manoeuvre geometry: the arcs' radii and the straights' lengths of named states,
laid over the state machine (config/conde_states.yaml), and the check that every arc the decision
drives is no tighter than the robot can turn.  Pure Python, no ROS.

The state machine's blind manoeuvres (the parking S, the turn into a bay) are drawn for Conde, a
differential-drive robot that turns on the spot.  A car turns no tighter than its minimum turning
radius (Major Alvega: 0.445 m at the rear-axle centre, from its URDF), so it needs its own radii and,
with them, other lengths.  A robot's manoeuvre file changes only those numbers:

    park_swing_out: {radius_m: 0.5, distance_m: 0.7005}   # state: the command fields it changes
    park_drive: {distance_m: 1.257}

Keys: a state of the state machine; fields: radius_m (only where the state drives an arc) and
distance_m, each a number > 0 [m].  Anything else is an error naming the file and the field.
"""

from dataclasses import replace
from typing import Dict, Optional

from conde_common.config_files import parse_yaml, read_text
from conde_decision.state_machine import _StrictLoader  # duplicate keys are errors, as in the state machine

#: The command fields a robot's manoeuvre file may change: the geometry of the manoeuvre [m].
MANOEUVRE_FIELDS = ("radius_m", "distance_m")


class ManoeuvreError(ValueError):
    """A manoeuvre file that cannot be used, or an arc tighter than the robot turns; the message
    names the file (or parameter) and the field."""


def parse_manoeuvres(data, source: str) -> Dict[str, Dict[str, float]]:
    """{state: {field: value [m]}} of a parsed manoeuvre file; `source` names it in errors."""
    if data is None:
        return {}
    if not isinstance(data, dict):
        raise ManoeuvreError("%s: expected a mapping of state names to {%s}, got %s"
                             % (source, ", ".join(MANOEUVRE_FIELDS), type(data).__name__))
    out = {}
    for state, fields in data.items():
        if not isinstance(fields, dict) or not fields:
            raise ManoeuvreError("%s: %s: expected a mapping with %s, got %r"
                                 % (source, state, " and/or ".join(MANOEUVRE_FIELDS), fields))
        out[str(state)] = {}
        for key, value in fields.items():
            if key not in MANOEUVRE_FIELDS:
                raise ManoeuvreError("%s: %s.%s: unknown field (expected %s)"
                                     % (source, state, key, " or ".join(MANOEUVRE_FIELDS)))
            if isinstance(value, bool) or not isinstance(value, (int, float)) or not value > 0 \
                    or value == float("inf"):
                raise ManoeuvreError("%s: %s.%s: expected a number > 0 [m], got %r" % (source, state, key, value))
            out[str(state)][key] = float(value)
    return out


def load_manoeuvres(path: str) -> Dict[str, Dict[str, float]]:
    """Reads and checks the manoeuvre file at `path`."""
    return parse_manoeuvres(parse_yaml(read_text(path, ManoeuvreError, "the manoeuvre file"), path,
                                       ManoeuvreError, "YAML error", loader=_StrictLoader), path)


def apply_manoeuvres(spec, manoeuvres: Dict[str, Dict[str, float]], source: str):
    """The StateMachineSpec `spec` with the manoeuvre fields of `manoeuvres` in its states'
    commands (a new spec; `spec` is unchanged).  A state the spec lacks, or a radius for a state
    that drives no arc, is a ManoeuvreError naming `source` and the state."""
    states = dict(spec.states)
    for name, fields in manoeuvres.items():
        if name not in states:
            raise ManoeuvreError("%s: %s: no such state in the state machine %s" % (source, name, spec.source))
        command = states[name].command
        if "radius_m" in fields and command.radius_m is None:
            raise ManoeuvreError("%s: %s.radius_m: the state drives no arc (its command has no radius_m)"
                                 % (source, name))
        states[name] = replace(states[name], command=replace(command, **fields))
    return replace(spec, states=states)


def tightest_arc(spec):
    """(state, radius [m]) of the tightest arc the state machine drives, None when it drives none."""
    arcs = [(s.name, s.command.radius_m) for s in spec.states.values() if s.command.radius_m is not None]
    return min(arcs, key=lambda arc: arc[1]) if arcs else None


def check_turning_radius(spec, min_turning_radius_m: float, robot: str,
                         manoeuvres: Optional[Dict[str, Dict[str, float]]] = None, manoeuvres_source: str = "",
                         spec_source: str = "") -> None:
    """ManoeuvreError for the first arc of `spec` tighter than `min_turning_radius_m` [m] (`robot`
    says where that radius comes from).  The message names where the radius was set: the
    manoeuvre file (`manoeuvres_source`) if it set it, else the state machine (`spec_source`)."""
    manoeuvres = manoeuvres or {}
    for state in spec.states.values():
        radius_m = state.command.radius_m
        if radius_m is None or radius_m >= min_turning_radius_m:
            continue
        if "radius_m" in manoeuvres.get(state.name, {}):
            where = "%s: %s.radius_m" % (manoeuvres_source, state.name)
        else:
            where = "%s: states.%s.command.radius_m" % (spec_source or spec.source, state.name)
        raise ManoeuvreError("%s: %.3f m is tighter than the robot's minimum turning radius %.3f m (%s); give the "
                             "state a radius >= %.3f m in the robot's manoeuvre file"
                             % (where, radius_m, min_turning_radius_m, robot, min_turning_radius_m))
