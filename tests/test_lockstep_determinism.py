"""Lock-step determinism of the main job, on each engine: the first RUN_S simulated seconds of the
autonomous run (D1: the robot waits for "forward" at 3 s, then follows the lane), in lock-step,
twice: once on the machine as it is (the test command runs other tests beside it) and once beside
CPU_HOGS more busy-looping processes started by the test. The ground-truth trajectories (every
/ground_truth/odom sample of the bag) must be equal bit for bit, and so must the referee's D1
reports. About 1 minute per engine."""
import json
import multiprocessing
import re
import subprocess

import pytest
import rosbag

ENGINES = ["ode", "bullet"]
RUN_S = 10.0  # [simulated s]
CPU_HOGS = 2


def busy_loop():
    while True:
        pass


def run(engine, out_dir):
    done = subprocess.run(["rosrun", "conde_eval", "autonomous_run", "--engine", engine, "--output-dir", str(out_dir),
                           "--sim-time-limit", str(RUN_S)], capture_output=True, text=True, timeout=600)
    out = done.stdout + done.stderr
    assert "| lock-step | yes, " in out and "| nodes that died | none |" in out, out[-4000:]
    timeouts = int(re.search(r"\| lock-step \| yes, (\d+) frames timed out", out).group(1))
    with rosbag.Bag(str(out_dir / f"autonomous_run_{engine}.bag")) as bag:
        samples = [(m.header.stamp.to_nsec(), m.pose.pose.position.x, m.pose.pose.position.y, m.pose.pose.position.z,
                    m.pose.pose.orientation.x, m.pose.pose.orientation.y, m.pose.pose.orientation.z,
                    m.pose.pose.orientation.w, m.twist.twist.linear.x, m.twist.twist.angular.z)
                   for _, m, _ in bag.read_messages(topics=["/ground_truth/odom"])]
    report = json.loads((out_dir / f"referee_D1_{engine}.json").read_text())
    return samples, report, timeouts, out


@pytest.mark.parametrize("engine", ENGINES)
def test_the_same_run_bit_for_bit_as_it_is_and_loaded(engine, tmp_path):
    reference, reference_report, reference_timeouts, reference_out = run(engine, tmp_path / "first")
    hogs = [multiprocessing.Process(target=busy_loop, daemon=True) for _ in range(CPU_HOGS)]
    for hog in hogs:
        hog.start()
    try:
        samples, report, timeouts, out = run(engine, tmp_path / "loaded")
    finally:
        for hog in hogs:
            hog.kill()
            hog.join()
    # The whole run is there: a sample every 20 ms up to RUN_S, and the robot drove (after "forward" at 3 s).
    assert len(reference) >= 0.95 * RUN_S / 0.02, reference_out[-3000:]
    assert reference[-1][0] >= (RUN_S - 0.1) * 1e9
    assert abs(reference[-1][1] - reference[0][1]) + abs(reference[-1][2] - reference[0][2]) > 1.0
    # Every answer came, from the first frame (the semaphore answers its first images with NONE).
    assert reference_timeouts == 0, reference_out[-3000:]
    assert len(samples) == len(reference), "loaded"
    first_difference = next((a for a, b in zip(reference, samples) if a != b), None)
    assert first_difference is None, f"loaded run parts at t = {first_difference[0] / 1e9} s"
    assert report == reference_report, "loaded"
    assert timeouts == reference_timeouts, out[-3000:]
