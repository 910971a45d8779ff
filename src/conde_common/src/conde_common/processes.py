"""Stopping a child started in its own session (subprocess.Popen(start_new_session=True)), such as
a roslaunch with its master and nodes: SIGINT to its whole process group, as Ctrl-C would, then
SIGKILL if it has not ended in time."""
import os
import signal
import subprocess


def stop_process_group(proc, timeout_s=30.0):
    """Stops proc's process group unless proc has ended; waits for proc [timeout_s wall, then kill]."""
    if proc is None or proc.poll() is not None:
        return
    os.killpg(proc.pid, signal.SIGINT)
    try:
        proc.wait(timeout=timeout_s)
    except subprocess.TimeoutExpired:
        os.killpg(proc.pid, signal.SIGKILL)
        proc.wait()
