"""The nodes of conde_racing against a real roscore on a free loopback port: ackermann_teleop in a
pseudo-terminal (keys in, commands out, a stop and the terminal restored on q and on SIGTERM, a
clear error without a terminal) and the exact start-up errors of lap_timer and gap_follower.
(The nodes driving the simulator are tested by tests/test_racing.py.)"""

import csv
import io
import os
import pty
import select
import signal
import subprocess
import termios
import threading
import time

import pytest

from conde_testing.ros_harness import Roscore

TOPIC = "/car9/ackermann_cmd"


@pytest.fixture(scope="module")
def core():
    with Roscore("conde_racing") as core:
        yield core


def read_until(fd, text, timeout_s=60.0):
    """Reads the pseudo-terminal until `text` shows up; returns what was read."""
    seen, end = b"", time.monotonic() + timeout_s
    while text.encode() not in seen:
        assert time.monotonic() < end, "no %r in %r" % (text, seen)
        if select.select([fd], [], [], 0.2)[0]:
            seen += os.read(fd, 4096)
    return seen.decode(errors="replace")


class Echo:
    """`rostopic echo -p` of the teleop's topic: rows of (speed, steering), read as they come."""

    def __init__(self, env):
        self.proc = subprocess.Popen(["rostopic", "echo", "-p", TOPIC], env=env, stdout=subprocess.PIPE,
                                     stderr=subprocess.DEVNULL, text=True)
        self._lines = []
        self._reader = threading.Thread(target=self._read, daemon=True)
        self._reader.start()

    def _read(self):
        for line in self.proc.stdout:
            self._lines.append(line)

    def rows(self):
        """The rows echoed so far."""
        reader = csv.DictReader(io.StringIO("".join(list(self._lines))))
        return [(float(r["field.drive.speed"]), float(r["field.drive.steering_angle"])) for r in reader]

    def rows_once(self, predicate, what, timeout_s=60.0):
        """The rows once predicate(rows) holds (another process's output: polled, not slept for)."""
        end = time.monotonic() + timeout_s
        while not predicate(self.rows()):
            assert time.monotonic() < end, "timed out waiting for %s: %r" % (what, self.rows()[-5:])
            time.sleep(0.1)
        return self.rows()

    def stop(self):
        self.proc.send_signal(signal.SIGINT)
        self.proc.wait(timeout=60)
        self._reader.join(timeout=60)


def start_teleop(core, *args):
    master_fd, slave_fd = pty.openpty()
    before = termios.tcgetattr(slave_fd)
    proc = subprocess.Popen(["rosrun", "conde_racing", "ackermann_teleop", "__ns:=car9"] + list(args), env=core.env,
                            stdin=slave_fd, stdout=slave_fd, stderr=slave_fd, start_new_session=True)
    return proc, master_fd, slave_fd, before


def wait_for_rows(echo_env, predicate, timeout_s=60.0):
    """Polls `rostopic echo -n 1` until the latest command satisfies predicate(speed, steering)."""
    end = time.monotonic() + timeout_s
    last = None
    while time.monotonic() < end:
        out = subprocess.run(["rostopic", "echo", "-n", "1", "-p", TOPIC], env=echo_env, capture_output=True,
                             text=True, timeout=60).stdout
        rows = list(csv.DictReader(io.StringIO(out)))
        if rows:
            last = (float(rows[-1]["field.drive.speed"]), float(rows[-1]["field.drive.steering_angle"]))
            if predicate(*last):
                return last
    raise AssertionError("the teleop's last command was %r" % (last,))


@pytest.mark.parametrize("how", ["q", "SIGTERM"])
def test_teleop_keys_drive_and_quitting_stops_and_restores_the_terminal(core, how):
    core.set_params({"/use_sim_time": False}, clear=["/ackermann_teleop", "/car9"])
    echo = Echo(core.env)
    proc, master_fd, slave_fd, before = start_teleop(core)
    try:
        read_until(master_fd, "driving %s" % TOPIC)
        os.write(master_fd, b"ww\x1b[D")                 # two steps faster, one step left (arrow)
        assert wait_for_rows(core.env, lambda v, s: v > 0) == (0.5, pytest.approx(0.05))
        if how == "q":
            os.write(master_fd, b"q")
        else:
            proc.send_signal(signal.SIGTERM)
        assert proc.wait(timeout=60) == 0
        assert "stopped the car" in read_until(master_fd, "stopped the car")
    finally:
        if proc.poll() is None:
            proc.kill()
    try:
        rows = echo.rows_once(lambda rows: rows and rows[-1][0] == 0.0, "the stop command in rostopic echo")
    finally:
        echo.stop()
    assert (0.5, pytest.approx(0.05)) in rows
    assert rows[-1][0] == 0.0, rows[-5:]
    assert termios.tcgetattr(slave_fd) == before
    os.close(master_fd)
    os.close(slave_fd)


def test_teleop_without_a_terminal_says_so(core):
    proc = subprocess.run(["rosrun", "conde_racing", "ackermann_teleop"], env=core.env, stdin=subprocess.DEVNULL,
                          capture_output=True, text=True, timeout=120)
    assert proc.returncode == 2
    assert proc.stderr.startswith("ackermann_teleop: error: standard input is not a terminal"), proc.stderr


def test_teleop_bad_limit(core):
    core.set_params({}, clear=["/ackermann_teleop"])
    proc, master_fd, slave_fd, _ = start_teleop(core, "_max_speed_mps:=-1")
    try:
        assert proc.wait(timeout=120) == 1
        text = read_until(master_fd, "\n")
        assert "ackermann_teleop: error: parameter /car9/ackermann_teleop/max_speed_mps: must be a number > 0, " \
               "got -1" in text
    finally:
        os.close(master_fd)
        os.close(slave_fd)


def error_lines(stderr, node):
    return [line for line in stderr.splitlines() if line.startswith(node + ": error: ")]


@pytest.mark.parametrize("node, params, message", [
    ("lap_timer", {}, "parameter /lap_timer/cars: expected a non-empty list of car namespaces, got None"),
    ("lap_timer", {"cars": ["car0", "car0"]}, "parameter /lap_timer/cars: a car is listed twice: ['car0', 'car0']"),
    ("lap_timer", {"cars": ["car0"]},
     "parameter /lap_timer/start_line_m is required: [[x, y], [x, y]] of the start/finish line"),
    ("lap_timer", {"cars": ["car0"], "start_line_m": [[0, 0], [0, 0]]},
     "parameter /lap_timer/start_line_m: expected [[x, y], [x, y]] in metres, got [[0, 0], [0, 0]] "
     "(the two ends of a line must differ, got (0.0, 0.0) twice)"),
    ("lap_timer", {"cars": ["car0"], "start_line_m": [[0, -1], [0, 1]], "checkpoints_m": [[[1, 2]]]},
     "parameter /lap_timer/checkpoints_m[0]: expected [[x, y], [x, y]] in metres, got [[1, 2]] "
     "(expected two points)"),
    ("lap_timer", {"cars": ["car0"], "start_line_m": [[0, -1], [0, 1]], "csv_path": "/no/such/dir/laps.csv"},
     "parameter /lap_timer/csv_path: directory /no/such/dir does not exist"),
    ("gap_follower", {"max_speed_mps": 0.0}, "parameter /gap_follower/max_speed_mps: must be > 0, got 0.0"),
    ("gap_follower", {"lookahead_m": "far"}, "parameter /gap_follower/lookahead_m: expected a number, got 'far'"),
    ("gap_follower", {"enabled": "yes"}, "parameter /gap_follower/enabled: expected true or false, got 'yes'"),
    ("gap_follower", {"start_delay_s": -1.0},
     "parameter /gap_follower/start_delay_s: expected a number >= 0 [s], got -1.0"),
])
def test_bad_parameters_exit_with_their_message(core, node, params, message):
    core.set_params({"/%s/%s" % (node, k): v for k, v in params.items()}, clear=["/" + node])
    proc = subprocess.run(["rosrun", "conde_racing", node], env=core.env, capture_output=True, text=True, timeout=120)
    assert proc.returncode == 1
    assert error_lines(proc.stderr, node) == [node + ": error: " + message]
