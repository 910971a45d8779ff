"""stop_process_group: SIGINT to a child's session, SIGKILL when it does not end in time."""
import signal
import subprocess
import sys

from conde_common.processes import stop_process_group


def child(code):
    return subprocess.Popen([sys.executable, "-c", code], start_new_session=True, stdout=subprocess.PIPE)


def test_a_child_and_its_own_children_end_on_sigint():
    proc = child("import subprocess, sys, time; subprocess.Popen([sys.executable, '-c', 'import time; "
                 "time.sleep(60)']); time.sleep(60)")
    stop_process_group(proc, timeout_s=30.0)
    assert proc.returncode != 0 and proc.poll() is not None


def test_a_child_that_ignores_sigint_is_killed_after_the_timeout():
    proc = child("import signal, time; signal.signal(signal.SIGINT, signal.SIG_IGN); print('ready', flush=True); "
                 "time.sleep(60)")
    assert proc.stdout.readline() == b"ready\n"  # SIGINT ignored from now on
    stop_process_group(proc, timeout_s=0.5)
    assert proc.returncode == -signal.SIGKILL


def test_an_ended_child_or_none_is_left_alone():
    proc = child("pass")
    proc.wait()
    stop_process_group(proc)
    stop_process_group(None)
    assert proc.returncode == 0
