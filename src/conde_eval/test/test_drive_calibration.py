"""conde_eval.drive_calibration and the calibrate command: the model, the fit and its uncertainty,
the paper's validation (1 m + 2 m -> 3 m), and named errors for bad input."""
import math
import os
import subprocess
import sys

import numpy as np
import pytest

from conde_eval import drive_calibration as dc
from conde_eval import evaluation_report as er

PACKAGE = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
PAPER_CSV = os.path.join(PACKAGE, "data", "conde_paper_runs.csv")
CALIBRATE = os.path.join(PACKAGE, "scripts", "calibrate")
XACRO_CALIBRATED = os.path.join(PACKAGE, "..", "..", "urdf", "scripts", "xacro_calibrated")


def synthetic_runs(values, noise_m, rng, lateral=False):
    runs = []
    for d in (1.0, 2.0, 3.0):
        for _ in range(5):
            dist, lat, _ = dc.predict_straight(values, d, 0.3)
            runs.append(dc.Run("straight", d, 0.3, dist + rng.normal(0, noise_m),
                               lateral_m=lat + rng.normal(0, noise_m) if lateral else None))
    for v in (0.3, 0.5):
        for _ in range(4):
            runs.append(dc.Run("square", 1.0, v, abs(dc.predict_square(values, 1.0, v) + rng.normal(0, noise_m))))
    return runs


def test_nominal_robot_without_latency_drives_exactly_and_closes_its_squares():
    dist, lateral, phi = dc.predict_straight(dc.NOMINAL, 2.0, 0.3)
    assert dist == pytest.approx(2.0, abs=1e-12) and lateral == pytest.approx(0.0, abs=1e-12)
    assert phi == pytest.approx(2.0 / 0.032)
    assert dc.predict_square(dc.NOMINAL, 1.0, 0.3) == pytest.approx(0.0, abs=1e-12)


def test_a_larger_right_wheel_curves_left_and_a_latency_overshoots():
    values = dict(dc.NOMINAL, radius_difference_m=0.0005, stop_latency_s=0.2)
    dist, lateral, _ = dc.predict_straight(values, 1.0, 0.5)
    assert lateral > 0.0
    assert dist == pytest.approx(1.1, abs=2e-3)  # 1 m + 0.5 m/s * 0.2 s, a slight arc


def test_fit_recovers_known_parameters_within_their_uncertainty():
    truth = dict(dc.NOMINAL, radius_mean_m=0.0309, radius_difference_m=0.0002, wheel_separation_m=0.345,
                 stop_latency_s=0.25)
    rng = np.random.default_rng(4)
    result = dc.fit(synthetic_runs(truth, 0.003, rng, lateral=True))
    assert set(result.fitted) == set(dc.PARAMETERS)
    for p in dc.PARAMETERS:
        assert abs(result.values[p] - truth[p]) < 3 * result.stderr[p], p
        assert result.stderr[p] < 0.2 * abs(truth[p]) + 1e-4, p  # informative, so the check above can fail


def test_the_stated_uncertainty_is_calibrated():
    """Over many noise draws about 95 % of the 2-sigma intervals of the mean radius hold the truth."""
    truth = dict(dc.NOMINAL, radius_mean_m=0.0315, stop_latency_s=0.3)
    rng = np.random.default_rng(7)
    hits = 0
    for _ in range(200):
        runs = [r for r in synthetic_runs(truth, 0.005, rng) if r.test == "straight"]
        result = dc.fit(runs, resolution_m=1e-6)
        hits += abs(result.values["radius_mean_m"] - truth["radius_mean_m"]) < 2 * result.stderr["radius_mean_m"]
    assert 0.88 <= hits / 200 <= 0.99


def test_paper_validation_predicts_the_3m_runs_from_the_1m_and_2m_runs_within_1_percent():
    val = er.paper_validation(dc.read_runs_csv(PAPER_CSV))
    assert set(val["fit12"].fitted) == {"radius_mean_m", "stop_latency_s"}
    assert abs(val["pred3_m"] - 3.069) / 3.069 < 0.01
    # the real mean lies within the prediction's 2-sigma band
    assert abs(val["pred3_m"] - 3.069) < 2 * val["pred3_se_m"]
    assert 0.0 < val["pred_sq05_m"] < 0.1


def test_straight_runs_cannot_identify_the_separation_nor_the_radius_difference():
    runs = [r for r in dc.read_runs_csv(PAPER_CSV) if r.test == "straight"]
    with pytest.raises(dc.NotIdentifiableError, match="wheel_separation_m cannot be identified.*turning runs"):
        dc.fit(runs, ["radius_mean_m", "wheel_separation_m"])
    with pytest.raises(dc.NotIdentifiableError, match="radius_difference_m cannot be identified.*lateral_m"):
        dc.fit(runs, ["radius_mean_m", "radius_difference_m"])
    one_distance = [r for r in runs if r.commanded_m == 1.0]
    with pytest.raises(dc.NotIdentifiableError, match="stop_latency_s cannot be identified.*two or more.*encoder"):
        dc.fit(one_distance, ["radius_mean_m", "stop_latency_s"])
    assert dc.fit(one_distance).fitted == ["radius_mean_m"]


def test_wheel_encoder_totals_identify_the_latency_from_one_distance():
    truth = dict(dc.NOMINAL, radius_mean_m=0.0312, stop_latency_s=0.35)
    rng = np.random.default_rng(3)
    runs = []
    for _ in range(4):
        dist, _, phi = dc.predict_straight(truth, 1.0, 0.3)
        runs.append(dc.Run("straight", 1.0, 0.3, dist + rng.normal(0, 0.002),
                           left_wheel_rad=phi + rng.normal(0, 0.05), right_wheel_rad=phi + rng.normal(0, 0.05)))
    result = dc.fit(runs)
    assert result.fitted == ["radius_mean_m", "stop_latency_s"]
    for p in result.fitted:
        assert abs(result.values[p] - truth[p]) < 3 * result.stderr[p], p
    without_encoders = [dc.Run(r.test, r.commanded_m, r.speed_mps, r.measured_m) for r in runs]
    assert dc.fit(without_encoders).fitted == ["radius_mean_m"]


def test_too_few_runs():
    runs = [dc.Run("straight", 1.0, 0.3, 1.1), dc.Run("straight", 2.0, 0.3, 2.09)]
    with pytest.raises(dc.NotIdentifiableError, match="too few runs to identify radius_mean_m, stop_latency_s: "
                                                      "2 measurements for 2 parameters"):
        dc.fit(runs)


@pytest.mark.parametrize("body, message", [
    ("test,commanded_m,speed_mps,measured_m\nstraight,1.0,0.3,abc\n",
     r"runs.csv:2: field 'measured_m': 'abc' is not a number"),
    ("# comment\ntest,commanded_m,speed_mps,measured_m\n\nstraight,1.0,0.3,1.1\nsquare,1.0,0.3,0.04\n",
     r"runs.csv:5: field 'turn_radps' is empty"),
    ("test,commanded_m,speed_mps,measured_m,turn_radps\nstraight,1.0,0.3,1.1,\ncircle,1.0,0.3,1.1,\n",
     r"runs.csv:3: field 'test': 'circle' \(expected one of straight, square\)"),
    ("test,commanded_m,speed_mps,measured_m\nstraight,1.0,0.3\n", r"runs.csv:2: 3 fields, the header has 4"),
    ("test,commanded_m,speed,measured_m\n", r"runs.csv:1: unknown column 'speed'"),
    ("test,commanded_m,measured_m\n", r"runs.csv:1: missing column 'speed_mps'"),
    ("test,commanded_m,speed_mps,measured_m\nstraight,-1,0.3,1.0\n",
     r"runs.csv:2: field 'commanded_m': -1 must be > 0"),
    ("test,commanded_m,speed_mps,measured_m\n", r"runs.csv: no runs after the header"),
])
def test_malformed_csv_names_file_line_and_field(tmp_path, body, message):
    path = tmp_path / "runs.csv"
    path.write_text(body)
    with pytest.raises(dc.DataError, match=message):
        dc.read_runs_csv(str(path))


def run_calibrate(*args, cwd):
    return subprocess.run([sys.executable, CALIBRATE, *args], capture_output=True, text=True, cwd=cwd, timeout=60)


def test_calibrate_command_bad_input_exits_2_with_the_message(tmp_path):
    bad = tmp_path / "bad.csv"
    bad.write_text("test,commanded_m,speed_mps,measured_m\nstraight,1.0,fast,1.1\n")
    proc = run_calibrate(str(bad), cwd=tmp_path)
    assert proc.returncode == 2
    assert f"calibrate: error: {bad}:2: field 'speed_mps': 'fast' is not a number" in proc.stderr
    few = tmp_path / "few.csv"
    few.write_text("test,commanded_m,speed_mps,measured_m\nstraight,1.0,0.3,1.1\n")
    proc = run_calibrate(str(few), "--fit", "radius_mean_m", cwd=tmp_path)
    assert proc.returncode == 2
    assert "too few runs to identify radius_mean_m: 1 measurements for 1 parameters" in proc.stderr
    proc = run_calibrate(PAPER_CSV, "--fit", "radius_difference_m", cwd=tmp_path)
    assert proc.returncode == 2 and "radius_difference_m cannot be identified" in proc.stderr
    assert not (tmp_path / "conde_calibration.yaml").exists()


def test_calibrate_command_writes_a_yaml_the_robot_xacro_uses(tmp_path):
    proc = run_calibrate(PAPER_CSV, "-o", "cal.yaml", cwd=tmp_path)
    assert proc.returncode == 0, proc.stderr
    assert "| wheel separation [m] | 0.33 |" in proc.stdout
    import yaml
    cal = yaml.safe_load((tmp_path / "cal.yaml").read_text())
    assert cal["wheel_radius_left_m"] == pytest.approx(cal["wheel_radius_right_m"])
    assert 0.030 < cal["wheel_radius_left_m"] < 0.032
    assert set(cal["fit"]["stderr"]) == {"wheel_radius_left_m", "wheel_radius_right_m", "wheel_separation_m",
                                         "stop_latency_s"}
    assert "radius_difference_m" in cal["fit"]["held_at_nominal"]
    # sim.launch's calibration:= path: the wheels take the calibrated radius, the diff drive keeps 0.064 m
    urdf = subprocess.run([sys.executable, XACRO_CALIBRATED, str(tmp_path / "cal.yaml"),
                           os.path.join(PACKAGE, "..", "..", "urdf", "robots", "conde.urdf.xacro"), "cameras:=false"],
                          capture_output=True, text=True, timeout=60)
    assert urdf.returncode == 0, urdf.stderr
    assert f'radius="{cal["wheel_radius_left_m"]!r}"' in urdf.stdout
    assert "<wheelDiameter>0.064</wheelDiameter>" in urdf.stdout
    (tmp_path / "partial.yaml").write_text("wheel_radius_left_m: 0.03\nwheel_radius_right_m: -1\n")
    bad = subprocess.run([sys.executable, XACRO_CALIBRATED, str(tmp_path / "partial.yaml"), "x.xacro"],
                         capture_output=True, text=True, timeout=60)
    assert bad.returncode == 2
    assert "partial.yaml: key 'wheel_radius_right_m': -1 is not a positive number [m]" in bad.stderr


def test_prediction_stderr_of_a_linear_prediction_matches_the_covariance():
    runs = [dc.Run("straight", d, 0.3, d * 1.01 + 0.05 + e) for d, e in
            ((1, 0.001), (1, -0.002), (2, 0.0), (2, 0.002), (3, -0.001))]
    result = dc.fit(runs)
    se = dc.prediction_stderr(result, lambda v: dc.predict_straight(v, 3.0, 0.3)[0])
    assert 0 < se < 0.01 and math.isfinite(se)


def test_closing_errors_have_a_mirror_separation_about_the_90_degree_turn():
    runs = dc.read_runs_csv(PAPER_CSV)
    val = er.paper_validation(runs)
    fitted = val["fit_all"].values["wheel_separation_m"]
    neutral = er.turn_neutral_separation_m(val["fit_all"].values)
    text = er.mirror_separation_text(val["fit_all"], runs)
    mirror = float(text.split("; a separation of ")[1].split(" m")[0])
    assert (fitted - neutral) * (mirror - neutral) < 0  # the other side
    # both separations give square closing errors inside the real range
    for b in (fitted, mirror):
        assert 0.02 < dc.predict_square(dict(val["fit_all"].values, wheel_separation_m=b), 1.0, 0.3) < 0.06
