"""Schedule files: parsing, the exact message of each invalid file, and signal_at."""
import os

import pytest

from conde_signalling_panel_control.schedule import (Schedule, ScheduleError, Step, load_schedule,
                                                     next_change_s, signal_at)

EXAMPLE = os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "config",
                       "example_schedule.yaml")
NAMES = "none, left, right, forward, stop, end_of_trial, parking"


def write(tmp_path, text, name="schedule.yaml"):
    path = tmp_path / name
    path.write_text(text)
    return str(path)


def test_valid_file(tmp_path):
    path = write(tmp_path, """
steps:
  - {at_s: 0.0, signal: stop}
  - {at_s: 5, signal: forward}
  - {at_s: 5.0, signal: left}
  - {at_s: 120.0, signal: end_of_trial}
""")
    schedule = load_schedule(path)
    assert schedule == Schedule((Step(0.0, "stop"), Step(5.0, "forward"), Step(5.0, "left"),
                                 Step(120.0, "end_of_trial")), "node_start")
    assert all(isinstance(step.at_s, float) for step in schedule.steps)


def test_start_on_first_clock(tmp_path):
    path = write(tmp_path, "start_on: first_clock\nsteps:\n  - {at_s: 1.5, signal: none}\n")
    assert load_schedule(path) == Schedule((Step(1.5, "none"),), "first_clock")


def test_example_schedule_of_the_package_is_valid():
    schedule = load_schedule(EXAMPLE)
    assert schedule.steps[0] == Step(0.0, "stop")
    assert schedule.steps[-1].signal == "end_of_trial"


ERROR_CASES = [
    ("steps:\n  - {at_s: 0.0, signal: stop}\n  - {at_s: 1.0, signal: left}\n  - {at_s: 2.0, signal: stp}\n",
     "{path}: steps[2]: unknown signal 'stp' (expected one of: " + NAMES + ")"),
    ("steps:\n  - {at_s: 0.0, signal: 3}\n",
     "{path}: steps[0]: unknown signal 3 (expected one of: " + NAMES + ")"),
    ("", "{path}: expected a mapping with the key 'steps'"),
    ("- {at_s: 0.0, signal: stop}\n", "{path}: expected a mapping with the key 'steps'"),
    ("step:\n  - {at_s: 0.0, signal: stop}\n", "{path}: unknown key 'step' (expected one of: steps, start_on)"),
    ("start_on: now\nsteps:\n  - {at_s: 0.0, signal: stop}\n",
     "{path}: start_on: unknown value 'now' (expected one of: node_start, first_clock)"),
    ("start_on: first_clock\n", "{path}: missing key 'steps'"),
    ("steps: []\n", "{path}: steps: expected a non-empty list of {{at_s, signal}}"),
    ("steps: {at_s: 0.0, signal: stop}\n", "{path}: steps: expected a non-empty list of {{at_s, signal}}"),
    ("steps:\n  - stop\n", "{path}: steps[0]: expected a mapping with the keys at_s, signal"),
    ("steps:\n  - {at: 0.0, signal: stop}\n", "{path}: steps[0]: unknown key 'at' (expected one of: at_s, signal)"),
    ("steps:\n  - {signal: stop}\n", "{path}: steps[0]: missing key 'at_s'"),
    ("steps:\n  - {at_s: 1.0}\n", "{path}: steps[0]: missing key 'signal'"),
    ("steps:\n  - {at_s: soon, signal: stop}\n",
     "{path}: steps[0]: at_s must be a finite number of seconds, got 'soon'"),
    ("steps:\n  - {at_s: true, signal: stop}\n",
     "{path}: steps[0]: at_s must be a finite number of seconds, got True"),
    ("steps:\n  - {at_s: .inf, signal: stop}\n",
     "{path}: steps[0]: at_s must be a finite number of seconds, got inf"),
    ("steps:\n  - {at_s: -1, signal: stop}\n", "{path}: steps[0]: at_s must be >= 0, got -1"),
    ("steps:\n  - {at_s: 5.0, signal: stop}\n  - {at_s: 2.5, signal: forward}\n",
     "{path}: steps[1]: at_s 2.5 is before the previous step's 5 (times must not decrease)"),
    ("steps:\n  - {at_s: 0.0, signal: stop\n", "{path}:3: invalid YAML: expected ',' or '}}', but got '<stream end>'"),
]


@pytest.mark.parametrize("text, message", ERROR_CASES)
def test_invalid_file_gives_its_exact_message(tmp_path, text, message):
    path = write(tmp_path, text)
    with pytest.raises(ScheduleError) as error:
        load_schedule(path)
    assert str(error.value) == message.format(path=path)


def test_missing_file(tmp_path):
    path = str(tmp_path / "no_such_schedule.yaml")
    with pytest.raises(ScheduleError) as error:
        load_schedule(path)
    assert str(error.value) == path + ": cannot read schedule: No such file or directory"


SCHEDULE = Schedule((Step(0.0, "stop"), Step(5.0, "forward"), Step(5.0, "left"), Step(120.0, "end_of_trial")),
                    "node_start")


def test_signal_at():
    assert signal_at(SCHEDULE, 0.0) == "stop"
    assert signal_at(SCHEDULE, 4.999) == "stop"
    assert signal_at(SCHEDULE, 5.0) == "left"  # the last of the steps at the same time wins
    assert signal_at(SCHEDULE, 119.9) == "left"
    assert signal_at(SCHEDULE, 120.0) == "end_of_trial"
    assert signal_at(SCHEDULE, 1e6) == "end_of_trial"
    later_start = Schedule((Step(2.0, "forward"),), "node_start")
    assert signal_at(later_start, 1.999) is None  # before the first step: keep the initial signal
    assert signal_at(later_start, 2.0) == "forward"


def test_next_change_s():
    assert next_change_s(SCHEDULE, 0.0) == 5.0
    assert next_change_s(SCHEDULE, 4.9) == 5.0
    assert next_change_s(SCHEDULE, 5.0) == 120.0
    assert next_change_s(SCHEDULE, 120.0) is None
    assert next_change_s(Schedule((Step(2.0, "stop"),), "node_start"), -1.0) == 2.0
