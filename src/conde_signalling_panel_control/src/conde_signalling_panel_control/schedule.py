"""Timed signal sequences read from YAML, for scripted runs of the signalling panel.

Format (times in simulated seconds since the schedule's start, non-decreasing, >= 0):

    start_on: node_start      # optional: node_start (default) | first_clock
    steps:
      - {at_s: 0.0, signal: stop}
      - {at_s: 5.0, signal: forward}
      - {at_s: 120.0, signal: end_of_trial}

start_on: node_start counts from the ROS time at which the node starts (under use_sim_time and
before the simulator publishes /clock that is time 0); first_clock counts from the first
non-zero ROS time the node sees, for clocks that do not start at 0 (e.g. a bag played with --clock).
"""
import math
from collections import namedtuple

from conde_common.config_files import parse_yaml, read_text
from conde_signalling_panel_control.signals import SIGNAL_NAMES, unknown_signal_message

START_ON_VALUES = ("node_start", "first_clock")
_TOP_KEYS = ("steps", "start_on")
_STEP_KEYS = ("at_s", "signal")

Step = namedtuple("Step", "at_s signal")
Schedule = namedtuple("Schedule", "steps start_on")  # steps: tuple of Step, sorted by at_s


class ScheduleError(ValueError):
    """A schedule file that cannot be used; the message names the file and the entry."""


def load_schedule(path):
    """Reads and validates a schedule file; raises ScheduleError."""
    text = read_text(path, ScheduleError, "schedule")
    return parse_schedule(parse_yaml(text, path, ScheduleError, "invalid YAML"), path)


def parse_schedule(data, source):
    """Validates already-parsed YAML data; `source` names the file in error messages."""
    if not isinstance(data, dict):
        raise ScheduleError("%s: expected a mapping with the key 'steps'" % source)
    for key in data:
        if key not in _TOP_KEYS:
            raise ScheduleError("%s: unknown key %r (expected one of: %s)" % (source, key, ", ".join(_TOP_KEYS)))
    start_on = data.get("start_on", "node_start")
    if start_on not in START_ON_VALUES:
        raise ScheduleError("%s: start_on: unknown value %r (expected one of: %s)"
                            % (source, start_on, ", ".join(START_ON_VALUES)))
    if "steps" not in data:
        raise ScheduleError("%s: missing key 'steps'" % source)
    raw_steps = data["steps"]
    if not isinstance(raw_steps, list) or not raw_steps:
        raise ScheduleError("%s: steps: expected a non-empty list of {at_s, signal}" % source)
    steps = []
    for index, raw in enumerate(raw_steps):
        where = "%s: steps[%d]" % (source, index)
        step = _parse_step(raw, where)
        if steps and step.at_s < steps[-1].at_s:
            raise ScheduleError("%s: at_s %g is before the previous step's %g (times must not decrease)"
                                % (where, step.at_s, steps[-1].at_s))
        steps.append(step)
    return Schedule(tuple(steps), start_on)


def _parse_step(raw, where):
    if not isinstance(raw, dict):
        raise ScheduleError("%s: expected a mapping with the keys %s" % (where, ", ".join(_STEP_KEYS)))
    for key in raw:
        if key not in _STEP_KEYS:
            raise ScheduleError("%s: unknown key %r (expected one of: %s)" % (where, key, ", ".join(_STEP_KEYS)))
    for key in _STEP_KEYS:
        if key not in raw:
            raise ScheduleError("%s: missing key %r" % (where, key))
    at_s = raw["at_s"]
    if isinstance(at_s, bool) or not isinstance(at_s, (int, float)) or not math.isfinite(at_s):
        raise ScheduleError("%s: at_s must be a finite number of seconds, got %r" % (where, at_s))
    if at_s < 0:
        raise ScheduleError("%s: at_s must be >= 0, got %g" % (where, at_s))
    signal = raw["signal"]
    if signal not in SIGNAL_NAMES:
        raise ScheduleError("%s: %s" % (where, unknown_signal_message(signal)))
    return Step(float(at_s), signal)


def signal_at(schedule, t_s):
    """The signal the schedule shows at t_s [s] since its start: that of the last step with
    at_s <= t_s; None before the first step (the panel keeps its initial signal)."""
    current = None
    for step in schedule.steps:
        if step.at_s > t_s:
            break
        current = step.signal
    return current


def next_change_s(schedule, t_s):
    """Time [s] of the first step after t_s, or None when no step is left."""
    for step in schedule.steps:
        if step.at_s > t_s:
            return step.at_s
    return None
