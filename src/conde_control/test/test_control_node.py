"""The conde_control node against a real roscore on a free loopback port, on simulated time owned
by the test: references in, /cmd_vel out at the node's rate within the limits, braking when the
references stop; a bad configuration stops it with the message and a non-zero exit; the CPU timing
line at shutdown."""

import json
import os
import re
import subprocess

import pytest

from conde_testing.ros_harness import Roscore, run_probe
from conde_control.control_law import ControlConfig

HERE = os.path.dirname(os.path.abspath(__file__))
LIMITS = ControlConfig()
PERIOD_S = 1.0 / 30.0
TIMING_LINE = re.compile(r"conde_control: timing: (\d+) frames, mean (\d+\.\d\d) ms, max (\d+\.\d\d) ms CPU per frame")


@pytest.fixture(scope="module")
def core():
    with Roscore("conde_control") as core:
        yield core


def test_reference_in_cmd_vel_out_and_braking_when_stale(core):
    core.set_params({"/use_sim_time": True}, clear=["/conde_control"])
    probe_out, log = run_probe(os.path.join(HERE, "control_probe.py"), ["rosrun", "conde_control", "conde_control"],
                               core.env, timeout_s=300)
    log_rows = json.loads(probe_out)
    follow = [(v, w) for phase, _, v, w in log_rows if phase == "follow"]
    silent = [(v, w) for phase, _, v, w in log_rows if phase == "silent"]
    assert len(follow) == 60 and len(silent) == 60

    # Following: speeds up to the reference at the acceleration limit; left of the lane centre,
    # so it turns right.
    assert follow[-1][0] == pytest.approx(0.5)
    assert all(w <= 0.0 for _, w in follow) and follow[-1][1] < -0.5
    # Stale 0.5 s (15 periods) after the last reference arrived, which was one period before the
    # silent phase: it keeps going until then ...
    assert all(v == pytest.approx(0.5) for v, _ in silent[:13]), str(silent[:20])
    assert silent[13][0] == pytest.approx(0.5 - LIMITS.max_linear_accel_mps2 * PERIOD_S)
    # ... then brakes to a stand.
    assert silent[-1] == (0.0, 0.0)
    assert "no reference on /conde_control_reference for 0.5 s: braking" in log

    # Every limit holds on the published commands (one command per period).
    cmds = [(0.0, 0.0)] + follow + silent
    for (v0, w0), (v1, w1) in zip(cmds, cmds[1:]):
        assert abs(v1) <= LIMITS.max_linear_mps + 1e-9 and abs(w1) <= LIMITS.max_angular_radps + 1e-9
        assert abs(v1 - v0) <= LIMITS.max_linear_accel_mps2 * PERIOD_S * 1.001
        assert abs(w1 - w0) <= LIMITS.max_angular_accel_radps2 * PERIOD_S * 1.001

    # The CPU timing at shutdown counts at least every iteration whose command the probe logged.
    timing = TIMING_LINE.findall(log)
    assert timing, "no timing line in the node log:\n" + log
    frames, mean_ms, max_ms = timing[-1]
    assert int(frames) >= len(follow) + len(silent) and 0.0 <= float(mean_ms) <= float(max_ms), timing[-1]


def test_bad_config_exits_with_the_message(core, tmp_path):
    path = tmp_path / "control.yaml"
    path.write_text("max_linear_mps: 0.5\nmax_speed: 2\n")
    core.set_params({}, clear=["/conde_control"])
    proc = subprocess.run(["rosrun", "conde_control", "conde_control", "_config:=%s" % path], env=core.env,
                          capture_output=True, text=True, timeout=120)
    assert proc.returncode != 0
    lines = [line for line in proc.stderr.splitlines() if line.startswith("conde_control: error: ")]
    assert lines == ["conde_control: error: %s: unknown key 'max_speed' (expected one of: offset_gain_per_m2, "
                     "heading_gain_per_m, max_linear_mps, max_angular_radps, max_linear_accel_mps2, "
                     "max_angular_accel_radps2)" % path], proc.stderr


def test_bad_rate_exits_with_the_message(core):
    core.set_params({}, clear=["/conde_control"])
    proc = subprocess.run(["rosrun", "conde_control", "conde_control", "_rate_hz:=0"], env=core.env,
                          capture_output=True, text=True, timeout=120)
    assert proc.returncode != 0
    assert "conde_control: error: parameter /conde_control/rate_hz: must be > 0, got 0" in proc.stderr.splitlines()
