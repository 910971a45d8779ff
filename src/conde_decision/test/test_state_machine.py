"""The YAML state machine: every transition of the default description fires, and each
validation error has its exact message."""

import os
from collections import deque

import pytest
import yaml

from conde_decision.state_machine import EVENTS, StateMachine, StateMachineError, load_state_machine

PACKAGE_DIR = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
DEFAULT_YAML = os.path.join(PACKAGE_DIR, "config", "conde_states.yaml")
FIXTURES = os.path.join(os.path.dirname(os.path.abspath(__file__)), "fixtures")
SPEC = load_state_machine(DEFAULT_YAML)
EVENT_LIST = ", ".join(EVENTS)


def path_to(spec, goal):
    """Shortest list of events that leads from the initial state to `goal`."""
    queue = deque([(spec.initial, [])])
    seen = {spec.initial}
    while queue:
        state, events = queue.popleft()
        if state == goal:
            return events
        for event, target in spec.states[state].transitions.items():
            if target not in seen and target != "return":  # `return` is not a state
                seen.add(target)
                queue.append((target, events + [event]))
    raise AssertionError("no path to %s" % goal)


def test_default_description():
    assert SPEC.initial == "wait_for_go"
    assert list(SPEC.states) == ["wait_for_go", "follow_lane", "turn_left", "turn_right", "approach_stop", "stopped",
                                 "approach_finish", "finished", "drive_to_parking", "parking_lead_in",
                                 "go_to_parking", "parked", "park_drive", "park_creep",
                                 "park_swing_out", "park_swing_in", "bay_drive_north", "bay_drive_south",
                                 "bay_approach", "bay_creep", "bay_turn_in", "bay_drive_in", "avoid_change_lane",
                                 "avoid_pass", "avoid_return"]
    assert SPEC.states["avoid_change_lane"].command.lane == "other"
    assert SPEC.states["avoid_return"].command.lane == "own"
    assert SPEC.states["turn_left"].command.branch == "left"
    assert SPEC.states["turn_right"].command.branch == "right"
    assert SPEC.states["go_to_parking"].command.distance_m is None  # leaves on the parking place's event
    assert SPEC.states["park_swing_out"].command.speed == "creep" and SPEC.states["bay_turn_in"].command.radius_m == 0.5
    assert SPEC.states["finished"].transitions == {}  # stays stopped
    for state in ("wait_for_go", "stopped", "finished", "parked"):
        assert SPEC.states[state].command.speed == "stop"


@pytest.mark.parametrize("source, event, target", SPEC.transitions(),
                         ids=["%s-%s" % (s, e) for s, e, _ in SPEC.transitions()])
def test_every_transition_fires(source, event, target):
    machine = StateMachine(SPEC)
    for e in path_to(SPEC, source):  # reach the source state through the machine itself
        assert machine.handle(e) is not None
    assert machine.state == source
    if target == "return":  # back to the state this one was entered from
        target = machine.previous
    assert machine.handle(event) == target
    assert machine.state == target and machine.last_event == event


def test_unlisted_events_are_ignored():
    machine = StateMachine(SPEC)
    assert machine.handle("signal_stop") is None  # waiting at the start: stop keeps waiting
    assert machine.handle("crosswalk_left") is None
    assert machine.state == "wait_for_go" and machine.last_event == ""
    with pytest.raises(ValueError, match="unknown event 'jump'"):
        machine.handle("jump")


# --- validation: exact messages -------------------------------------------------------------------

def write(tmp_path, data, name="conde_states.yaml"):
    path = tmp_path / name
    path.write_text(data if isinstance(data, str) else yaml.safe_dump(data, sort_keys=False))
    return str(path)


def default_data():
    with open(DEFAULT_YAML) as f:
        return yaml.load(f, Loader=yaml.BaseLoader)  # strings only: `on` stays a key


def error_of(path):
    with pytest.raises(StateMachineError) as info:
        load_state_machine(path)
    return str(info.value)


def modified(tmp_path, change):
    data = default_data()
    for state in data["states"].values():  # BaseLoader keeps numbers as strings
        for key in ("distance_m", "radius_m"):
            if key in state["command"]:
                state["command"][key] = float(state["command"][key])
    change(data)
    return write(tmp_path, data)


def in_command(state, edit):
    """A change of the default description: `edit` applied to the command of `state`."""
    return lambda d: edit(d["states"][state]["command"])


def without_the_parking_signal(d):
    for state in ("wait_for_go", "follow_lane", "approach_stop", "stopped", "approach_finish"):
        d["states"][state]["on"].pop("signal_parking")


# (id, change of the default description, message after "<file>: ")
MODIFIED = [
    ("unknown_target_state", lambda d: d["states"]["follow_lane"]["on"].update(signal_stop="stoped"),
     "states.follow_lane.on.signal_stop: unknown target state 'stoped'"),
    ("unknown_event", lambda d: d["states"]["follow_lane"]["on"].update(see_stop="approach_stop"),
     f"states.follow_lane.on.see_stop: unknown event 'see_stop' (expected one of: {EVENT_LIST})"),
    ("unknown_initial_state", lambda d: d.update(initial="start"), "initial: unknown state 'start'"),
    ("missing_initial", lambda d: d.pop("initial"), "missing key 'initial'"),
    ("unknown_top_level_key", lambda d: d.update(version=2),
     "unknown key 'version' (expected one of: initial, states)"),
    ("unknown_state_key", lambda d: d["states"]["stopped"].update(colour="red"),
     "states.stopped: unknown key 'colour' (expected one of: description, command, on)"),
    ("unknown_command_key", in_command("stopped", lambda c: c.update(lane="left")),
     "states.stopped.command.lane: unknown lane 'left' (expected one of: own, other)"),
    ("unknown_speed", in_command("follow_lane", lambda c: c.update(speed="fast")),
     "states.follow_lane.command.speed: unknown speed 'fast' (expected one of: cruise, stop, stop_at_crosswalk, "
     "stop_at_finish, creep, reverse)"),
    ("missing_speed", in_command("follow_lane", lambda c: c.pop("speed")),
     "states.follow_lane.command: missing key 'speed'"),
    ("missing_command", lambda d: d["states"]["parked"].pop("command"), "states.parked: missing key 'command'"),
    ("unknown_branch", in_command("turn_left", lambda c: c.update(branch="up")),
     "states.turn_left.command.branch: unknown branch 'up' (expected one of: none, left, right)"),
] + [
    ("bad_distance-%s" % value, in_command("turn_left", lambda c, v=value: c.update(distance_m=v)),
     f"states.turn_left.command.distance_m: expected a distance > 0 [m], got {value!r}") for value in (0, -1.0, "far")
] + [
    ("distance_event_without_distance", in_command("turn_left", lambda c: c.pop("distance_m")),
     "states.turn_left.on.distance_elapsed: the state has no command.distance_m, so the event never fires"),
    ("lane_aligned_without_an_arc", lambda d: d["states"]["follow_lane"]["on"].update(lane_aligned="stopped"),
     "states.follow_lane.on.lane_aligned: the state has no command.radius_m and command.distance_m (an arc), "
     "so the event never fires"),
    ("unreachable_state", without_the_parking_signal,
     "states.drive_to_parking: unreachable from the initial state 'wait_for_go'"),
    ("transitions_must_be_a_mapping", lambda d: d["states"]["stopped"].update(on=["signal_forward"]),
     "states.stopped.on: expected a mapping of events to states"),
    ("return_is_not_a_state_name", lambda d: d["states"].update({"return": {"command": {"speed": "stop"}}}),
     "states.return: 'return' is a reserved target (back to the previous state), not a state name"),
    ("an_arc_needs_a_branch", in_command("turn_left", lambda c: c.update(branch="none")),
     "states.turn_left.command.radius_m: an arc needs a branch (left or right) to turn toward"),
]


@pytest.mark.parametrize("change, message", [case[1:] for case in MODIFIED], ids=[case[0] for case in MODIFIED])
def test_invalid_description(tmp_path, change, message):
    path = modified(tmp_path, change)
    assert error_of(path) == f"{path}: {message}"


@pytest.mark.parametrize("text, message", [
    ("initial: a\nstates: {}\n", "states: expected a non-empty mapping of state names to states"),
    ("- initial\n", "expected a mapping with keys initial and states, got list"),
], ids=["states_must_be_a_non_empty_mapping", "not_a_mapping"])
def test_invalid_file(tmp_path, text, message):
    path = write(tmp_path, text)
    assert error_of(path) == f"{path}: {message}"


def test_unknown_target_state_fixture():
    path = os.path.join(FIXTURES, "unknown_state.yaml")
    assert error_of(path) == f"{path}: states.follow_lane.on.signal_stop: unknown target state 'stoped'"


def test_duplicate_key(tmp_path):
    text = open(DEFAULT_YAML).read().replace("      signal_stop: approach_stop\n",
                                             "      signal_stop: approach_stop\n      signal_stop: stopped\n", 1)
    path = write(tmp_path, text)
    line = text.splitlines().index("      signal_stop: stopped") + 1
    assert error_of(path) == f"{path}:{line}: YAML error: duplicate key 'signal_stop'"


def test_missing_file(tmp_path):
    path = str(tmp_path / "none.yaml")
    assert error_of(path) == f"{path}: cannot read the state machine: No such file or directory"


def test_yaml_syntax_error(tmp_path):
    path = write(tmp_path, "initial: [a\n")
    assert error_of(path) == f"{path}:2: YAML error: expected ',' or ']', but got '<stream end>'"  # and the line


def test_on_is_a_key_not_a_boolean(tmp_path):
    # YAML 1.1 reads a bare `on` as True; this loader keeps it a key (and `on` as a value a string).
    path = write(tmp_path, "initial: a\nstates:\n  a:\n    command: {speed: stop}\n    on: {signal_forward: b}\n"
                           "  b:\n    description: on\n    command: {speed: cruise}\n")
    spec = load_state_machine(path)
    assert spec.states["a"].transitions == {"signal_forward": "b"}
    assert spec.states["b"].description == "on"


def test_return_goes_back_to_the_state_a_turn_was_entered_from():
    machine = StateMachine(SPEC)
    for event, state in (("signal_forward", "follow_lane"), ("signal_stop", "approach_stop"),
                         ("merge_right", "turn_right"), ("distance_elapsed", "approach_stop"),
                         ("signal_forward", "follow_lane"), ("merge_left", "turn_left"),
                         ("distance_elapsed", "follow_lane")):
        assert machine.handle(event) == state
