"""The main job end to end, on each engine: the simulator, the panels playing the two-lap
schedule, semaphore, tracking, decision and control, with their own ROS master.  The run must
finish two laps without leaving its lane (judged by conde_eval/autonomous_run from ground truth
and the track geometry) and leave its plot, bag and summary behind.  About 3.5 minutes per engine."""
import re
import subprocess

import pytest

ENGINES = ["ode", "bullet"]
# Paced to the wall clock: the simulation does not wait for the Python nodes, so on a busy machine
# a faster run lets them fall behind (the junctions' blind turns then start late).
REAL_TIME_FACTOR = 1.0


@pytest.mark.parametrize("engine", ENGINES)
def test_two_autonomous_laps(engine, tmp_path):
    run = subprocess.run(["rosrun", "conde_eval", "autonomous_run", "--engine", engine, "--output-dir", str(tmp_path),
                          "--real-time-factor", str(REAL_TIME_FACTOR), "--sim-time-limit", "260"],
                         capture_output=True, text=True, timeout=1800)
    out = run.stdout + run.stderr
    assert run.returncode == 0 and "RESULT: PASS" in out, out[-4000:]
    laps = re.findall(r"^\| (\d) \| ([\d.]+) \|$", out, re.M)
    assert [n for n, _ in laps] == ["1", "2"], out[-4000:]
    for _, lap_s in laps:  # a lap of the lane at 0.5 m/s is about 82 s
        assert 75.0 < float(lap_s) < 110.0
    assert re.search(r"\| stayed in its lane \| yes \|", out)
    assert re.search(r"\| points off the road \| 0 of \d+ \|", out)
    for name in (f"autonomous_run_{engine}.png", f"autonomous_run_{engine}.bag"):
        path = tmp_path / name
        assert path.is_file() and path.stat().st_size > 10_000, name
