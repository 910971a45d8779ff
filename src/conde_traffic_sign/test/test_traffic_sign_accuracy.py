"""traffic_sign_accuracy's argument errors: each names the argument and exits 2 before any
simulation is started."""
import os
import subprocess
import sys

import pytest

SCRIPT = os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "scripts", "traffic_sign_accuracy")


def run(*args):
    env = dict(os.environ, PYTHONPATH=os.pathsep.join(p for p in sys.path if p))
    env.pop("ROS_MASTER_URI", None)  # nothing may be started or reached
    return subprocess.run([sys.executable, SCRIPT, *args], capture_output=True, text=True, env=env, timeout=60)


@pytest.mark.parametrize("args, message", [
    (("--camera", "fisheye"), "argument --camera: invalid choice: 'fisheye' (choose from 'signs_rear', 'top')"),
    (("--camera",), "argument --camera: expected one argument"),
    (("--camera", "signs_rear", "--samples", "0"), "--samples must be >= 1"),
    (("--camera", "signs_rear", "--track-seeds", "-1"), "--track-seeds must be >= 0"),
    (("--connect", "--track-seeds", "0", "1"), "--connect renders on the running simulator's one track"),
])
def test_a_bad_argument_is_named_and_nothing_runs(args, message):
    proc = run(*args)
    assert proc.returncode == 2, proc.stderr
    assert message in proc.stderr
    assert proc.stdout == ""


def test_the_help_names_both_cameras():
    proc = run("--help")
    assert proc.returncode == 0, proc.stderr
    assert "{signs_rear,top}" in proc.stdout
