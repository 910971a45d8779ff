"""The conde_decision node against a real roscore on a free loopback port: lane measurements and
panel signals in, control reference, state and marker out, on simulated time owned by the test;
bad input stops it with the message and a non-zero exit; the CPU timing line at shutdown."""

import json
import os
import re
import subprocess

import pytest

from conde_testing.ros_harness import Roscore, fatal_error, run_probe

HERE = os.path.dirname(os.path.abspath(__file__))
FIXTURES = os.path.join(HERE, "fixtures")
TIMING_LINE = re.compile(r"conde_decision: timing: (\d+) frames, mean (\d+\.\d\d) ms, max (\d+\.\d\d) ms CPU per frame")


@pytest.fixture(scope="module")
def core():
    with Roscore("conde_decision") as core:
        yield core


def run_node(core, **params):
    """Runs conde_decision until it exits by itself; returns (exit code, stderr)."""
    core.set_params({}, clear=["/conde_decision"])
    args = ["rosrun", "conde_decision", "conde_decision"] + ["_%s:=%s" % kv for kv in params.items()]
    proc = subprocess.run(args, env=core.env, capture_output=True, text=True, timeout=120)
    return proc.returncode, proc.stderr


def startup_error(core, **params):
    """The message of a start of conde_decision that must fail."""
    return fatal_error(*run_node(core, **params), "conde_decision")


def test_lane_and_signal_in_reference_and_state_out(core):
    core.set_params({"/use_sim_time": True}, clear=["/conde_decision"])
    # Lock-step (~input_wait_s): a measurement waits for the panel signal of the previous frame, which
    # the probe sends with every measurement, as conde_semaphore does with every image.
    probe_out, log = run_probe(os.path.join(HERE, "decision_probe.py"),
                               ["rosrun", "conde_decision", "conde_decision", "_input_wait_s:=30"],
                               core.env, timeout_s=300)
    result = json.loads(probe_out)
    refs, states, markers = result["refs"], result["states"], result["markers"]

    # One reference per lane message, stamped with the measurement's time, measurement passed on.
    speeds = [r[6] for r in refs]
    start = next((i for i, v in enumerate(speeds) if v > 0.0), None)  # the measurement that took the go
    # The go signal was stamped with measurement 9 (index): applied at 10, neither at 9 itself nor
    # later, however late its own connection delivered it.
    assert start == 10, speeds
    assert len(refs) == start + 30  # the probe measures 29 more after it
    assert all(r[1] == "base_footprint" and r[2] == 0.05 and r[3] == 0.0 and r[4] == 0.02 and r[5] == 0.0
               for r in refs)
    assert refs[0][0] == pytest.approx(1.0 + 1 / 30.0, abs=1e-6)
    assert speeds[:start] == [0.0] * start  # waiting for the go signal
    # After "forward": ramps up at 1 m/s^2 (1/30 m/s per message) and holds 0.5 m/s.
    assert speeds[start] == pytest.approx(1 / 30.0, abs=1e-6)
    assert speeds[start + 14:] == [pytest.approx(0.5)] * 16

    # The state: at start, on the change (with the event, the signal and the time of the measurement
    # that applied it, although that frame's clock reached the node after the measurement), then at
    # 1 Hz.
    assert states[0][1:] == ["wait_for_go", "", 0]
    change = [s for s in states if s[1] == "follow_lane"]
    assert change[0][1:] == ["follow_lane", "signal_forward", 3]
    assert change[0][0] == pytest.approx(refs[start][0], abs=1e-6)
    assert len(change) >= 4  # the change plus at least 3 periodic messages over 3.5 s
    # The repeats are stamped with the whole seconds of ROS time they are due at, whenever the node
    # got to read its clock.
    periodic_stamps = [s[0] for s in change[1:]]
    assert periodic_stamps == [pytest.approx(round(t), abs=1e-6) for t in periodic_stamps], str(states)
    assert all(b - a == pytest.approx(1.0, abs=1e-6) for a, b in zip(periodic_stamps, periodic_stamps[1:])), str(states)

    # The marker for rviz: text above the robot.
    frame, marker_type, text, z = markers[-1]
    assert frame == "base_footprint" and marker_type == 9 and z > 0.3  # 9 = TEXT_VIEW_FACING
    assert text.splitlines()[0] == "follow_lane" and "signal forward" in text
    # ... logged with the measurement's simulated time and the distance driven
    assert "wait_for_go --signal_forward--> follow_lane (t = %.2f s, 0.00 m driven)" % refs[start][0] in log, log

    # The CPU timing at shutdown counts every lane measurement.
    timing = TIMING_LINE.findall(log)
    assert timing, "no timing line in the node log:\n" + log
    frames, mean_ms, max_ms = timing[-1]
    assert int(frames) == len(refs) and 0.0 <= float(mean_ms) <= float(max_ms), timing[-1]


def test_unknown_state_exits_with_the_message(core):
    path = os.path.join(FIXTURES, "unknown_state.yaml")
    assert startup_error(core, state_machine=path) == (
        f"{path}: states.follow_lane.on.signal_stop: unknown target state 'stoped'")


def test_missing_state_machine_file_exits_with_the_message(core):
    path = os.path.join(FIXTURES, "no_such_states.yaml")
    assert startup_error(core, state_machine=path) == (
        f"{path}: cannot read the state machine: No such file or directory")


def test_bad_parameter_exits_with_the_message(core):
    assert startup_error(core, cruise_speed_mps=-1.0) == (
        "parameter /conde_decision/cruise_speed_mps: must be > 0, got -1.0")


def test_bad_avoidance_parameter_exits_with_the_message(core):
    """AvoidanceConfig's fields are the node's parameters too."""
    assert startup_error(core, avoid_trigger_m=0.0) == (
        "parameter /conde_decision/avoid_trigger_m: expected a finite number > 0, got 0.0")
