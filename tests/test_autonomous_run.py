"""The main job end to end, on each engine: the simulator, the panels playing the two-lap
schedule, semaphore, tracking, decision and control, with their own ROS master.  The run must
finish two laps without leaving its lane (judged by conde_eval/autonomous_run from ground truth
and the track geometry) and leave its plot, bag and summary behind, with the referee's D1 score.
In lock-step (autonomous_run's default), so a busy machine only makes it slower."""
import re
import subprocess

import pytest

ENGINES = ["ode", "bullet"]


@pytest.mark.parametrize("engine", ENGINES)
def test_two_autonomous_laps(engine, tmp_path):
    run = subprocess.run(["rosrun", "conde_eval", "autonomous_run", "--engine", engine, "--output-dir", str(tmp_path),
                          "--sim-time-limit", "260"],
                         capture_output=True, text=True, timeout=1800)
    out = run.stdout + run.stderr
    assert run.returncode == 0 and "RESULT: PASS" in out, out[-4000:]
    laps = re.findall(r"^\| (\d) \| ([\d.]+) \|$", out, re.M)
    assert [n for n, _ in laps] == ["1", "2"], out[-4000:]
    for _, lap_s in laps:  # a lap of the lane at 0.5 m/s is about 82 s
        assert 75.0 < float(lap_s) < 110.0
    assert re.search(r"\| stayed in its lane \| yes \|", out)
    assert re.search(r"\| lock-step \| yes, \d+ frames timed out \|", out)
    assert re.search(r"\| points off the road \| 0 of \d+ \|", out)
    # conde_referee's D1 judgement of the run (placeholder rules) is in the summary.
    assert re.search(r"^\| referee, D1 score \(placeholder rules\) \| -?[\d.]+ \(penalties [\d.]+, laps 2, ", out,
                     re.M), out[-4000:]
    for name in (f"autonomous_run_{engine}.png", f"autonomous_run_{engine}.bag"):
        path = tmp_path / name
        assert path.is_file() and path.stat().st_size > 10_000, name


def descendants(root_pid):
    """{pid: command line} of every process below root_pid."""
    out = subprocess.run(["ps", "-e", "-o", "pid=,ppid=,args="], capture_output=True, text=True, check=True).stdout
    rows = [line.split(None, 2) for line in out.splitlines()]
    children = {}
    for pid, ppid, *args in rows:
        children.setdefault(int(ppid), []).append((int(pid), args[0] if args else ""))
    found, todo = {}, [root_pid]
    while todo:
        for pid, args in children.get(todo.pop(), []):
            found[pid] = args
            todo.append(pid)
    return found


def test_a_simulator_that_dies_is_named_with_its_signal(tmp_path):
    """SIGKILL to the simulator in the middle of a run: the run fails and says which node died and
    how (it used to say "roslaunch stopped (exit 0)")."""
    run = subprocess.Popen(["rosrun", "conde_eval", "autonomous_run", "--output-dir", str(tmp_path),
                            "--sim-time-limit", "260"],
                           stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, start_new_session=True)
    try:
        lines = []
        for line in run.stdout:  # progress lines come every 10 s of simulated time
            lines.append(line)
            if re.search(r"\] sim +([1-9]\d*\.\d) s", line):
                break
        simulators = [pid for pid, args in descendants(run.pid).items() if "conde_sim_node" in args.split(" ")[0]]
        assert len(simulators) == 1, "".join(lines)
        subprocess.run(["kill", "-KILL", str(simulators[0])], check=True)
        out = "".join(lines) + run.stdout.read()
        run.wait(timeout=120)
    finally:
        if run.poll() is None:
            subprocess.run(["kill", "-KILL", f"-{run.pid}"])
    assert run.returncode != 0, out[-3000:]
    assert f"conde_sim (pid {simulators[0]}) died: killed by SIGKILL" in out, out[-3000:]
    assert "RESULT: FAIL" in out
