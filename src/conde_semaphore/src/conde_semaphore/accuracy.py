"""Shared parts of the accuracy scripts (semaphore_accuracy, semaphore_start_accuracy): the image
degradation, the confusion table and starting / stopping panel_rendering.launch on a free port.
The start poses of the grid come from conde_worlds (start_pose_grid, pure)."""
import os
import socket
import subprocess
import tempfile

import numpy as np

from conde_common.panel_signals import SIGNAL_NAMES
from conde_common.processes import stop_process_group

#: The challenges whose start poses the grid covers: crosswalk (D*, P*, V1) and before_bays (B*).
GRID_CHALLENGES = {"crosswalk": "P1", "before_bays": "B2"}


def degrade(image, brightness, noise_sigma, rng):
    """Image scaled in brightness, plus Gaussian noise of sigma noise_sigma (fraction of 255)."""
    pixels = image.astype(np.float32) * brightness
    pixels += rng.normal(0.0, noise_sigma * 255.0, size=image.shape).astype(np.float32)
    return np.clip(np.rint(pixels), 0, 255).astype(np.uint8)


def confusion_table(confusion):
    """Markdown confusion matrix: rows the true signal, columns the classified one."""
    header = "| true \\ classified | " + " | ".join(SIGNAL_NAMES) + " | accuracy |"
    lines = [header, "|---" * (len(SIGNAL_NAMES) + 2) + "|"]
    for i, name in enumerate(SIGNAL_NAMES):
        total = confusion[i].sum()
        accuracy = "%.1f %%" % (100.0 * confusion[i, i] / total) if total else "-"
        lines.append("| %s | %s | %s |" % (name, " | ".join(str(v) for v in confusion[i]), accuracy))
    return "\n".join(lines)


def start_pose_grid(track_seed, placement_seeds, starts=tuple(GRID_CHALLENGES)):
    """[(start name, placement seed, x_m, y_m, yaw_rad)] of Conde's start poses on a track seed:
    each named start (challenges.yaml start_poses) carried over to the track and moved by each
    placement seed, as generate_challenge places the robot."""
    from conde_worlds import placement
    from conde_worlds.challenge_world import start_poses
    from conde_worlds.challenges import load_challenges
    from conde_worlds.track_variation import track_dimensions

    challenges = load_challenges()
    dims = track_dimensions(track_seed)
    grid = []
    for start in starts:
        nominal = start_poses(challenges.challenges[GRID_CHALLENGES[start]].start, dims)
        for seed in placement_seeds:
            pose = placement.placed_poses(nominal, seed, challenges.start_area)["conde"]
            grid.append((start, seed, float(pose["xyz"][0]), float(pose["xyz"][1]), float(pose["yaw"])))
    return grid


def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def start_rendering(engine="ode", launch_args=()):
    """roslaunch of panel_rendering.launch on a free port, its own master; sets ROS_MASTER_URI in
    this process's environment; returns the process (own session, roslaunch's stderr in .log)."""
    port = free_port()
    os.environ.update(ROS_MASTER_URI="http://127.0.0.1:%d" % port, ROS_IP="127.0.0.1")
    os.environ.pop("ROS_HOSTNAME", None)
    log = tempfile.TemporaryFile()  # roslaunch's stderr, shown if the simulation cannot be reached
    launch = subprocess.Popen(
        ["roslaunch", "-p", str(port), "conde_semaphore", "panel_rendering.launch", "physics_engine:=" + engine]
        + list(launch_args), stdout=subprocess.DEVNULL, stderr=log, start_new_session=True)
    launch.log = log
    return launch


def launch_error(launch, error):
    """The error text, with roslaunch's stderr if it has exited."""
    if launch is not None and launch.poll() is not None:
        launch.log.seek(0)
        output = launch.log.read().decode(errors="replace")
        return "%s\nroslaunch exited with %d:\n%s" % (error, launch.returncode, output)
    return str(error)


def stop_simulation(launch):
    stop_process_group(launch)
