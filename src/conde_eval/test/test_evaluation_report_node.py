"""evaluation_report --quick end to end on both engines: the simulator runs, the semaphore
accuracy and the field-of-view gtest (about a minute); then the report's files and tables."""
import json
import os
import subprocess

import pytest

from conde_eval import evaluation_report as er


@pytest.fixture(scope="module")
def report(tmp_path_factory):
    out = tmp_path_factory.mktemp("evaluation_report")
    proc = subprocess.run(["rosrun", "conde_eval", "evaluation_report", "--quick", "--output-dir", str(out)],
                          capture_output=True, text=True, timeout=600)
    return out, proc


def test_quick_report_runs_every_part_on_both_engines(report):
    out, proc = report
    assert proc.returncode == 0, proc.stdout[-3000:] + proc.stderr[-3000:]
    assert "[ode] 3 runs done" in proc.stdout and "[bullet] 3 runs done" in proc.stdout  # progress lines
    results = json.loads((out / "evaluation_results.json").read_text())
    assert results["problems"] == []
    for engine in ("ode", "bullet"):
        rows = results["odometry"][engine]
        assert [r["kind"] for r in rows] == ["straight", "square", "square"]
        assert all(r["by_distance"] for r in rows)
        # driven by distance reference: the encoder odometry stops it just past 1 m
        assert 1.0 < rows[0]["travelled_m"] < 1.05
        assert results["semaphore"][engine]["samples"] == 20
        assert results["semaphore"][engine]["correct"] >= 18
    assert len(results["field_of_view"]) == 3
    mh, mv, _ = er.fov_errors(results["field_of_view"])
    assert mh < 0.5 and mv < 0.5
    assert abs(results["validation"]["pred3_error_pct"]) < 1.0


def test_quick_report_files(report):
    out, _ = report
    for name in ("evaluation_report.md", "evaluation_report.pdf", "straight_runs.png", "squares.png",
                 "semaphore.png", "field_of_view.png"):
        assert (out / name).stat().st_size > 1000, name
    import yaml
    calibration = yaml.safe_load((out / "conde_calibration_paper.yaml").read_text())
    assert 0.030 < calibration["wheel_radius_left_m"] < 0.032
    assert (out / "evaluation_report.pdf").read_bytes()[:5] == b"%PDF-"
    text = (out / "evaluation_report.md").read_text()
    assert "| commanded | real robot (paper) | paper's Gazebo (error vs real) | ode (error vs real) | " \
           "bullet (error vs real) |" in text
    assert "| 1 m | 1.097–1.107 m (mid-range 1.102) | 1.150–1.154 m (4.65 %) |" in text
    assert "99.37 % of 700 images" in text
    assert "**Quick version**" in text
    for png in ("straight_runs.png", "squares.png", "semaphore.png", "field_of_view.png"):
        assert f"]({png})" in text and os.path.exists(out / png)
