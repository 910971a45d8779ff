"""Runs of odometry_test.launch (the simulator paused + odometry_test_node) in a subprocess with
its own ROS master on a free loopback port: shared by odometry_test, evaluation_report and the
calibration tests. No rospy here; it only starts roslaunch and reads the JSON it writes."""
import json
import os
import re
import signal
import socket
import subprocess
import threading
import time

from conde_common.processes import stop_process_group

PROGRESS = re.compile(r"(run \d+/\d+ [^:{]*)")


def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def run_odometry(engine, output_dir, tag="", launch_args=(), timeout_s=900, progress=print):
    """One engine's odometry scenarios; returns the list of result rows, or None on failure (the
    last lines of the log are passed to `progress`). `launch_args`: extra `name:=value` arguments of
    odometry_test.launch (protocol, repeats, distances, squares, robot_args, calibration)."""
    name = f"odometry_{engine}{tag}"
    result = os.path.join(output_dir, f"{name}.json")
    log = os.path.join(output_dir, f"{name}.log")
    if os.path.exists(result):
        os.remove(result)
    port = free_port()
    # unbuffered: the node's "run i/N" lines reach the progress output as they happen
    env = dict(os.environ, ROS_MASTER_URI=f"http://127.0.0.1:{port}", ROS_IP="127.0.0.1", PYTHONUNBUFFERED="1")
    env.pop("ROS_HOSTNAME", None)
    started = time.monotonic()
    progress(f"[{engine}] launching conde_sim and the odometry scenarios (log: {log})")
    with open(log, "w") as out:
        proc = subprocess.Popen(["roslaunch", "-p", str(port), "conde_eval", "odometry_test.launch",
                                 f"physics_engine:={engine}", f"output:={result}", *launch_args],
                                stdout=subprocess.PIPE, stderr=subprocess.STDOUT, env=env, text=True,
                                start_new_session=True)
        timer = threading.Timer(timeout_s, lambda: os.killpg(proc.pid, signal.SIGINT))
        timer.start()
        try:
            for line in proc.stdout:
                out.write(line)
                found = PROGRESS.search(line)
                if found:  # odometry_test_node: "run 3/23 straight 1 m at 0.3 m/s: {...}"
                    progress(f"[{engine}] {found.group(1)}")
            proc.wait()
        finally:
            timer.cancel()
            stop_process_group(proc)  # interrupted: stop the simulation and its master too
        status = f"roslaunch exit {proc.returncode}" if time.monotonic() - started < timeout_s else \
            f"stopped after the time limit of {timeout_s} s"
    wall_s = time.monotonic() - started
    if not os.path.exists(result):
        with open(log) as f:
            tail = "".join(f.readlines()[-25:])
        progress(f"[{engine}] FAILED after {wall_s:.1f} s ({status}); last lines of the log:\n{tail}")
        return None
    with open(result) as f:
        rows = json.load(f)
    progress(f"[{engine}] {len(rows)} runs done in {wall_s:.1f} s")
    return rows
