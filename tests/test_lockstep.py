"""Lock-step (conde_sim ~lockstep) against the real node on each engine: Conde on the competition
track, paused, a lock-step rule that makes the simulator wait for an answer to each left
ground-camera image. A slow answering node (tests/lockstep_answerer.py, it sleeps per image)
must never see the simulated time run ahead of the image it answers; with nobody answering, the
run still reaches ~max_sim_time and counts one timed-out frame per image."""
import os
import re
import subprocess
import sys

import pytest

from conde_testing.ros_harness import stop_process

ENGINES = ["ode", "bullet"]
HERE = os.path.dirname(os.path.abspath(__file__))
IMAGE = "/conde_camera_tracking_left/image_raw"
CAMERA_RATE_HZ = 30.0


def write_config(path, answer, timeout_s):
    path.write_text(f"timeout_s: {timeout_s}\nrules:\n  - answer: {answer}\n    inputs: [{IMAGE}]\n")
    return str(path)


def launch_sim(env, engine, config, max_sim_time_s):
    # Set before the answering node starts (sim.launch sets it too, maybe later).
    subprocess.run(["rosparam", "set", "/use_sim_time", "true"], env=env, check=True, timeout=60)
    return subprocess.Popen(
        ["roslaunch", "conde_bringup", "sim.launch", f"physics_engine:={engine}", "paused:=true", "lockstep:=true",
         f"lockstep_config:={config}", f"max_sim_time:={max_sim_time_s}", "real_time_factor:=0"],
        env=env, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, start_new_session=True)


def start_answerer(env, answer, delay_s, wait_for_listener=True):
    return subprocess.Popen([sys.executable, os.path.join(HERE, "lockstep_answerer.py"), f"_image:={IMAGE}",
                             f"_answer:={answer}", f"_delay_s:={delay_s}",
                             f"_wait_for_listener:={'true' if wait_for_listener else 'false'}"],
                            env=env, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)


def unpause(env):
    # --wait: the silent-node test starts its answerer without waiting for the simulator's listener,
    # so the service may not be advertised yet (CI: "rosservice call" exit status 2).
    subprocess.run(["rosservice", "call", "--wait", "/conde_sim/unpause_physics"], env=env, check=True,
                   capture_output=True, timeout=120)


def lockstep_summary(out):
    """(frames waited, frames timed out) from the simulator's last words."""
    m = re.search(r"lock-step: (\d+) frames waited for answers, (\d+) timed out", out)
    assert m, out[-3000:]
    return int(m.group(1)), int(m.group(2))


@pytest.mark.parametrize("engine", ENGINES)
def test_slow_node_holds_the_simulated_time(master, engine, tmp_path):
    sim_s = 2.0
    config = write_config(tmp_path / "lockstep.yaml", "/slow_answer", timeout_s=5.0)
    sim = launch_sim(master, engine, config, sim_s)
    answerer = start_answerer(master, "/slow_answer", delay_s=0.05)
    try:
        assert answerer.stdout.readline().strip() == "ready"
        unpause(master)
        out, _ = sim.communicate(timeout=600)
    finally:
        stop_process(sim, group=True)
        stop_process(answerer)
    answers = [tuple(map(float, line.split()[1:3])) for line in answerer.stdout.read().splitlines()
               if line.startswith("answer ")]
    waited, timed_out = lockstep_summary(out)
    frames = int(sim_s * CAMERA_RATE_HZ)
    assert timed_out == 0, out[-3000:]
    assert frames - 2 <= waited <= frames + 1, out[-3000:]
    assert len(answers) >= frames - 2, answers
    # The node sleeps 50 ms of wall time per image; the simulator, as fast as it can otherwise, must
    # not have moved on: the time the node sees when it answers is the image's own (/clock at 1 kHz).
    ahead = [round(now - stamp, 4) for stamp, now in answers if now - stamp > 0.0015]
    assert not ahead, f"simulated time ran ahead of the answers by {ahead} s"


@pytest.mark.parametrize("engine", ENGINES)
def test_silent_node_times_out_and_the_run_goes_on(master, engine, tmp_path):
    sim_s = 1.0
    config = write_config(tmp_path / "lockstep.yaml", "/never_answered", timeout_s=0.05)
    sim = launch_sim(master, engine, config, sim_s)
    # It takes the images (the camera publishes only to listeners) and answers on another topic.
    listener = start_answerer(master, "/not_what_was_asked", delay_s=0.0, wait_for_listener=False)
    try:
        assert listener.stdout.readline().strip() == "ready"
        unpause(master)
        out, _ = sim.communicate(timeout=300)  # ~max_sim_time ends the run: no deadlock
    finally:
        stop_process(sim, group=True)
        stop_process(listener)
    waited, timed_out = lockstep_summary(out)
    frames = int(sim_s * CAMERA_RATE_HZ)
    assert frames - 1 <= timed_out <= frames + 1, out[-3000:]
    assert timed_out == waited
    assert "conde_sim: lock-step: /never_answered: " in out and "no answer within 0.050 s" in out
    assert "reached ~max_sim_time_s = 1.000 s" in out
