"""The competition runner for real (rosrun conde_tournament competition, what scripts/run_demo.sh
runs after the build): P1 with the Conde stack, the real simulator (ODE), lock-step and the
referee, stopped at 20 s of simulated time; the table's row and the summary page agree with the
referee's JSON report, and the report and path plot are where the summary links them.
About 1 minute on a busy 2-core machine."""
import json
import os
import subprocess

from conde_testing.ros_harness import workspace_env

TIMEOUT_S = 600


def test_competition_runs_p1_and_its_table_is_the_referees(tmp_path):
    out_dir = tmp_path / "competition"
    run = subprocess.run(["rosrun", "conde_tournament", "competition", "--challenge", "P1", "--sim-limit", "20",
                          "--output-dir", str(out_dir)], env=workspace_env("conde_tournament"),
                         capture_output=True, text=True, timeout=TIMEOUT_S)
    assert run.returncode == 0, run.stdout[-4000:] + run.stderr[-4000:]
    folder = out_dir / "P1" / "challenge"
    for name in ("referee.json", "referee.md", "referee.png"):
        assert (folder / name).is_file(), name
    report = json.loads((folder / "referee.json").read_text())
    assert report["challenge"] == "P1" and report["kind"] == "parking"
    # The row of the table: challenge, result, time, penalties, score, wall.
    lines = run.stdout.splitlines()
    header = next(i for i, line in enumerate(lines) if line.startswith("challenge  result"))
    row = lines[header + 2]
    assert row.startswith("P1 "), run.stdout
    passed = bool(report["parked"]) and not report["disqualified"]
    assert ("PASS" if passed else "FAIL") in row and (report["end"] or "not ended") in row, (row, report)
    cells = row.split()
    time_cell = "-" if report["driving_time_s"] is None else "%.1f" % report["driving_time_s"]
    assert cells[-4:-1] == [time_cell, "%g" % report["penalty_total"], "%.1f" % report["score"]], (row, report)
    assert lines[header + 4].startswith("total      %d/1 passed" % passed), run.stdout
    md = (out_dir / "summary.md").read_text()
    assert "![P1 path](P1/challenge/referee.png)" in md
    assert "| P1 | %s (" % ("PASS" if passed else "FAIL") in md
    assert '<img src="P1/challenge/referee.png"' in (out_dir / "summary.html").read_text()
    assert os.path.getsize(folder / "referee.png") > 1000
