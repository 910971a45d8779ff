"""stop_process_group on real processes: a group that stops on SIGINT, one that ignores it (then
SIGKILL after the timeout) and a process that has exited already."""
import os
import signal
import subprocess
import time

from conde_common.process_groups import stop_process_group


def group(script):
    return subprocess.Popen(["bash", "-c", script], start_new_session=True)


def test_sigint_stops_the_group():
    process = group("trap 'exit 5' INT; sleep 60 & wait")
    time.sleep(0.3)
    started = time.monotonic()
    try:
        assert stop_process_group(process, timeout_s=10.0) == 5  # the group leader got SIGINT
        assert time.monotonic() - started < 5.0
    finally:  # bash's background sleep ignores SIGINT (non-interactive shell): not left behind
        try:
            os.killpg(process.pid, signal.SIGKILL)
        except ProcessLookupError:
            pass


def test_a_group_ignoring_sigint_is_killed_after_the_timeout():
    process = group("trap '' INT; sleep 60")
    time.sleep(0.3)
    started = time.monotonic()
    assert stop_process_group(process, timeout_s=0.5) == -signal.SIGKILL
    assert time.monotonic() - started < 10.0


def test_an_exited_process_is_left_alone():
    process = group("exit 3")
    process.wait()
    assert stop_process_group(process) == 3
