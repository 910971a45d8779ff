"""Stopping a process started with start_new_session=True (e.g. a roslaunch with its own master)
together with its children: what the measurement scripts that launch a simulation share."""
import os
import signal
import subprocess


def stop_process_group(process, timeout_s=30.0):
    """SIGINT to the process group `process` leads (what Ctrl-C sends: roslaunch shuts its nodes
    down), SIGKILL if it has not exited within timeout_s [s]; nothing if it has exited already.
    Returns the exit status."""
    if process.poll() is None:
        for sig in (signal.SIGINT, signal.SIGKILL):
            try:
                os.killpg(process.pid, sig)
            except ProcessLookupError:  # the group has ended meanwhile
                pass
            try:
                process.wait(timeout=timeout_s)
                break
            except subprocess.TimeoutExpired:
                continue
        process.wait()
    return process.returncode
