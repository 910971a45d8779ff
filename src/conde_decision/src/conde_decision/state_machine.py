"""A state machine described in YAML, validated when it is loaded.  Pure Python, no ROS.

File format (see config/conde_states.yaml):

    initial: wait_for_go              # the state at start-up
    states:
      follow_lane:
        description: free text         # optional
        command:                       # what the robot does in this state
          speed: cruise                # cruise | stop | stop_at_crosswalk | stop_at_finish | creep | reverse
                                       # (creep / reverse: slowly forward / backward, blind:
                                       # an arc with branch and radius_m, else straight on)
          branch: none                 # none | left | right (optional, default none)
          distance_m: 2.2              # optional: the event distance_elapsed fires after
                                       # driving this far [m] in the state
          radius_m: 1.391              # optional, with a branch: drive an arc of this radius
                                       # toward the branch instead of following the lane
        on:                            # transitions: event -> next state
          signal_stop: approach_stop

Validation (a StateMachineError whose message names the file, the state and the key):
unknown top-level, state or command keys; unknown events (the fixed vocabulary EVENTS);
unknown target states; a missing or unknown initial state; `distance_elapsed` in a state without
`command.distance_m`; and states that cannot be reached from the initial state (an error, not a
warning: in a machine this small an unreachable state is always a typo or a forgotten
transition).  Duplicate keys in a mapping are errors too (YAML would keep the last silently).

Events not listed in a state's `on` are ignored in that state.  A transition to the state itself
is allowed (it restarts the state's distance count).  The target `return` goes back to the state
the current one was entered from (e.g. a turn returns to following the lane, or to approaching
the crosswalk to stop there); `return` is therefore not a state name.
"""

import re
from collections import OrderedDict
from dataclasses import dataclass, field
from typing import Dict, List, Optional, Tuple

import yaml
from conde_common.config_files import parse_yaml, read_text

#: The events the decision logic (decision_logic.py) produces, with what makes each fire.
EVENTS = OrderedDict([
    ("signal_forward", "a panel signal FORWARD was received (every message, confidence high enough)"),
    ("signal_left", "a panel signal LEFT was received"),
    ("signal_right", "a panel signal RIGHT was received"),
    ("signal_stop", "a panel signal STOP was received"),
    ("signal_end_of_trial", "a panel signal END_OF_TRIAL was received"),
    ("signal_parking", "a panel signal PARKING was received"),
    ("crosswalk_reached", "the robot came within crosswalk_zone_m of the near edge of the crosswalk ahead "
                          "(after having left the crosswalk; the start counts as being at it)"),
    ("lap_completed", "a crosswalk_reached that completes a lap (every crossings_per_lap-th one)"),
    ("crosswalk_left", "base_footprint passed the far edge of the crosswalk"),
    ("fork_left", "the fork after the crosswalk is reached, the panel ordered left and the fork opens left"),
    ("fork_right", "the fork after the crosswalk is reached, the panel ordered right and the fork opens right"),
    ("fork_straight", "the fork after the crosswalk is reached and the robot keeps straight"),
    ("merge_left", "the loop driven after a fork_straight ends where its road joins the central road "
                   "with a left turn"),
    ("merge_right", "the loop driven after a fork_straight ends where its road joins the central road "
                    "with a right turn"),
    ("distance_elapsed", "the robot drove the state's command.distance_m since it entered the state"),
    ("parking_parallel", "the parking place chosen is the parallel bay (fires in every step)"),
    ("parking_bay_north", "the parking place chosen is the north bay of the bay-parking area (every step)"),
    ("parking_bay_south", "the parking place chosen is the south bay of the bay-parking area (every step)"),
    # Parking on what the cameras see (parking_place auto, conde_decision/parking.py):
    ("parking_bays_seen", "parking_place auto: a bay of the bay-parking area is known (two of its lines seen)"),
    ("bay_entry_near", "a free bay is known and the robot has reached the point before its centre line where "
                       "the straight and the turn into it (the states this event leads to) begin"),
    ("park_entry_near", "the free stretch of the parallel bay is known (its start or the boxes in it seen) and the "
                        "robot has reached the point where the manoeuvre into its middle (the states this event "
                        "leads to) begins"),
    ("lane_aligned", "in an arc driven blind (command.radius_m), past lane_aligned_min_sweep of its sweep, the cameras "
                     "confirm the lane it leads to (lane_aligned_frames frames of one lane, both lines) and the robot "
                     "heads along it as the lane follower would (arc_end.py)"),
    # Obstacles and the working zone (conde_decision/avoidance.py):
    ("obstacle_ahead", "a box or cone in the robot's lane, within avoid_trigger_m ahead (conde_tracking's obstacles)"),
    ("lane_changed", "in a state with command.lane other, the robot has reached the other lane's centre"),
    ("obstacle_passed", "every box or cone seen in the robot's own lane is avoid_clearance_m behind the robot"),
    ("lane_returned", "in a state with command.lane own after a lane change, the robot is back on its lane's centre"),
])

SPEEDS = ("cruise", "stop", "stop_at_crosswalk", "stop_at_finish", "creep", "reverse")
BRANCHES = ("none", "left", "right")
LANES = ("own", "other")  # command.lane: drive in the robot's own lane or in the other (left) lane
TOP_KEYS = ("initial", "states")
STATE_KEYS = ("description", "command", "on")
COMMAND_KEYS = ("speed", "branch", "distance_m", "radius_m", "lane")
RETURN = "return"  # transition target: back to the state the current one was entered from


class StateMachineError(ValueError):
    """A state-machine description that cannot be used; the message names file, state and key."""


@dataclass(frozen=True)
class Command:
    """What the robot does in a state."""

    speed: str  # one of SPEEDS
    branch: str = "none"  # one of BRANCHES
    distance_m: Optional[float] = None  # distance_elapsed fires after this many metres
    radius_m: Optional[float] = None  # with a branch: drive an arc of this radius toward it [m]
    lane: str = "own"  # one of LANES: "other" moves the lateral reference onto the other lane's centre


@dataclass(frozen=True)
class State:
    name: str
    command: Command
    transitions: Dict[str, str] = field(default_factory=dict)  # event -> next state
    description: str = ""


@dataclass(frozen=True)
class StateMachineSpec:
    """A validated description: the initial state and the states by name (file order)."""

    initial: str
    states: Dict[str, State]
    source: str = ""

    def transitions(self) -> List[Tuple[str, str, str]]:
        """Every (state, event, next state) of the description, in file order."""
        return [(s.name, e, t) for s in self.states.values() for e, t in s.transitions.items()]


class _StrictLoader(yaml.SafeLoader):
    """SafeLoader that rejects duplicate keys in a mapping and, as YAML 1.2 does, reads only
    true/false as booleans (YAML 1.1 would turn the key `on` into True)."""


_BOOL_TAG = "tag:yaml.org,2002:bool"
_StrictLoader.yaml_implicit_resolvers = {
    first: [(tag, regexp) for tag, regexp in resolvers if tag != _BOOL_TAG]
    for first, resolvers in yaml.SafeLoader.yaml_implicit_resolvers.items()}
_StrictLoader.add_implicit_resolver(_BOOL_TAG, re.compile(r"^(?:true|True|TRUE|false|False|FALSE)$"), list("tTfF"))


def _construct_mapping(loader, node, deep=False):
    loader.flatten_mapping(node)
    seen = set()
    for key_node, _ in node.value:
        key = loader.construct_object(key_node, deep=deep)
        if key in seen:
            raise yaml.constructor.ConstructorError(None, None, "duplicate key '%s'" % (key,), key_node.start_mark)
        seen.add(key)
    return loader.construct_mapping(node, deep)


_StrictLoader.add_constructor(yaml.resolver.BaseResolver.DEFAULT_MAPPING_TAG, _construct_mapping)


def load_state_machine(path: str) -> StateMachineSpec:
    """Reads and validates a state-machine YAML file."""
    text = read_text(path, StateMachineError, "the state machine")
    data = parse_yaml(text, path, StateMachineError, "YAML error", loader=_StrictLoader)
    return parse_state_machine(data, path)


def parse_state_machine(data, source: str) -> StateMachineSpec:
    """Validates already parsed data; `source` (the file) starts every error message."""

    def fail(where: str, what: str):
        raise StateMachineError("%s: %s: %s" % (source, where, what) if where else "%s: %s" % (source, what))

    def expect_keys(mapping, known, where):
        for key in mapping:
            if key not in known:
                fail(where, "unknown key '%s' (expected one of: %s)" % (key, ", ".join(known)))

    if not isinstance(data, dict):
        fail("", "expected a mapping with keys initial and states, got %s" % type(data).__name__)
    expect_keys(data, TOP_KEYS, "")
    for key in TOP_KEYS:
        if key not in data:
            fail("", "missing key '%s'" % key)
    raw_states = data["states"]
    if not isinstance(raw_states, dict) or not raw_states:
        fail("states", "expected a non-empty mapping of state names to states")

    states = OrderedDict()
    for name, raw in raw_states.items():
        where = "states.%s" % name
        if not isinstance(name, str) or not name:
            fail("states", "state names must be non-empty strings, got %r" % (name,))
        if name == RETURN:
            fail(where, "'%s' is a reserved target (back to the previous state), not a state name" % RETURN)
        if not isinstance(raw, dict):
            fail(where, "expected a mapping with keys %s" % ", ".join(STATE_KEYS))
        expect_keys(raw, STATE_KEYS, where)
        if "command" not in raw:
            fail(where, "missing key 'command'")
        command = _parse_command(raw["command"], where + ".command", fail)
        description = raw.get("description", "")
        if not isinstance(description, str):
            fail(where + ".description", "expected a string")
        transitions = raw.get("on") or {}
        if not isinstance(transitions, dict):
            fail(where + ".on", "expected a mapping of events to states")
        for event, target in transitions.items():
            if event not in EVENTS:
                fail("%s.on.%s" % (where, event), "unknown event '%s' (expected one of: %s)"
                     % (event, ", ".join(EVENTS)))
            if event == "distance_elapsed" and command.distance_m is None:
                fail("%s.on.%s" % (where, event), "the state has no command.distance_m, so the event never fires")
            if event == "lane_aligned" and (command.radius_m is None or command.distance_m is None):
                fail("%s.on.%s" % (where, event),
                     "the state has no command.radius_m and command.distance_m (an arc), so the event never fires")
        states[name] = State(name, command, dict(transitions), description)

    for name, state in states.items():
        for event, target in state.transitions.items():
            if target not in states and target != RETURN:
                fail("states.%s.on.%s" % (name, event), "unknown target state '%s'" % (target,))

    initial = data["initial"]
    if initial not in states:
        fail("initial", "unknown state '%s'" % (initial,))

    reached = {initial}
    frontier = [initial]
    while frontier:
        for target in states[frontier.pop()].transitions.values():
            if target not in reached and target != RETURN:
                reached.add(target)
                frontier.append(target)
    for name in states:
        if name not in reached:
            fail("states.%s" % name, "unreachable from the initial state '%s'" % initial)

    return StateMachineSpec(initial, dict(states), source)


def _parse_command(raw, where, fail) -> Command:
    if not isinstance(raw, dict):
        fail(where, "expected a mapping with keys %s" % ", ".join(COMMAND_KEYS))
    for key in raw:
        if key not in COMMAND_KEYS:
            fail(where, "unknown key '%s' (expected one of: %s)" % (key, ", ".join(COMMAND_KEYS)))
    if "speed" not in raw:
        fail(where, "missing key 'speed'")
    speed = raw["speed"]
    if speed not in SPEEDS:
        fail(where + ".speed", "unknown speed '%s' (expected one of: %s)" % (speed, ", ".join(SPEEDS)))
    branch = raw.get("branch", "none")
    if branch not in BRANCHES:
        fail(where + ".branch", "unknown branch '%s' (expected one of: %s)" % (branch, ", ".join(BRANCHES)))
    distance_m = raw.get("distance_m")
    if distance_m is not None:
        if isinstance(distance_m, bool) or not isinstance(distance_m, (int, float)) or not distance_m > 0:
            fail(where + ".distance_m", "expected a distance > 0 [m], got %r" % (distance_m,))
        distance_m = float(distance_m)
    radius_m = raw.get("radius_m")
    if radius_m is not None:
        if isinstance(radius_m, bool) or not isinstance(radius_m, (int, float)) or not radius_m > 0:
            fail(where + ".radius_m", "expected a radius > 0 [m], got %r" % (radius_m,))
        if branch == "none":
            fail(where + ".radius_m", "an arc needs a branch (left or right) to turn toward")
        radius_m = float(radius_m)
    lane = raw.get("lane", "own")
    if lane not in LANES:
        fail(where + ".lane", "unknown lane '%s' (expected one of: %s)" % (lane, ", ".join(LANES)))
    return Command(speed, branch, distance_m, radius_m, lane)


class StateMachine:
    """The running machine: the current state and the event that led to it."""

    def __init__(self, spec: StateMachineSpec):
        self.spec = spec
        self.state = spec.initial
        self.previous = spec.initial  # the state the current one was entered from
        self.last_event = ""

    @property
    def command(self) -> Command:
        return self.spec.states[self.state].command

    def handle(self, event: str) -> Optional[str]:
        """Applies one event; returns the new state if a transition fired (possibly the same
        state again), None if the current state ignores the event."""
        if event not in EVENTS:
            raise ValueError("unknown event '%s'" % event)
        target = self.spec.states[self.state].transitions.get(event)
        if target is None:
            return None
        if target == RETURN:
            target = self.previous
        self.previous = self.state
        self.state = target
        self.last_event = event
        return target
