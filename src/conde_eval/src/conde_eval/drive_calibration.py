"""Calibration of a differential-drive robot model from measured runs (pure Python: numpy, scipy).

The runs follow the seed paper's protocol, *driving by distance reference*: the robot's own
controller believes the nominal geometry (wheel radius `NOMINAL_WHEEL_RADIUS_M`, separation
`NOMINAL_WHEEL_SEPARATION_M`), drives at `speed_mps` and stops when its encoder odometry says the
commanded distance is done. What really happens depends on the robot's true (effective) geometry:

- straight run: both wheels turn by phi = (commanded_m + speed_mps * stop_latency_s) / r_nominal
  [rad] (the motors go on for `stop_latency_s` after the stop command; braking is lumped into it);
  the wheels roll r_left * phi and r_right * phi, an arc of heading change
  (r_right - r_left) * phi / separation. Measured: the chord (start-to-end distance) [m] and,
  optionally, the sideways offset at the end (+ left) [m] and the wheel angles [rad].
- square: four times a side driven as the straight run, then a left turn *timed* at turn_radps
  for pi / (2 turn_radps) s (a pure delay shifts a timed command but does not lengthen it). The
  turn really turns phi_t * (r_left + r_right) / separation with
  phi_t = pi/2 * separation_nominal / (2 r_nominal). Measured: the closing error [m], the
  distance from the start to the end position.

What the data identify (the fit refuses a parameter the data cannot move):

- straight distances alone: the mean wheel radius (a distance scale); with two or more
  commanded distances also the stop overshoot speed * stop_latency_s (the latency itself only
  because the speed is known; separating a delay from braking needs runs at several speeds);
- wheel encoder totals (left_wheel_rad, right_wheel_rad) of straight runs: the overshoot in wheel
  angle, i.e. the stop latency, even from one commanded distance (with the distances, then, the
  mean radius too); in this model both wheels turn alike, so they say nothing about the sides;
- the radius *difference* left/right: only the sideways offset of straight runs (lateral_m);
  closing errors alone mix it with the separation;
- the wheel separation: only turning runs (squares), given the mean radius.

Parameters are fitted with scipy.optimize.least_squares; their standard errors come from the
Jacobian at the solution: cov = s^2 (J^T J)^-1 with s^2 the residual variance (at least the
measurement resolution squared).
"""
import csv
import math
from dataclasses import dataclass, field
from typing import Dict, List, Optional, Sequence

import numpy as np
from scipy.optimize import least_squares

NOMINAL_WHEEL_RADIUS_M = 0.032     # conde.urdf.xacro: wheel_radius
NOMINAL_WHEEL_SEPARATION_M = 0.33  # conde.urdf.xacro: wheel_separation
DEFAULT_RESOLUTION_M = 0.001       # a tape measure's millimetre: floor of the residual scale

#: Fit parameters, in the order of the parameter vector, with the nominal (start) values.
#: radius_mean_m and radius_difference_m (right - left) are fitted rather than the two radii,
#: because straight distances identify the mean and nothing else.
PARAMETERS = ("radius_mean_m", "radius_difference_m", "wheel_separation_m", "stop_latency_s")
NOMINAL = {"radius_mean_m": NOMINAL_WHEEL_RADIUS_M, "radius_difference_m": 0.0,
           "wheel_separation_m": NOMINAL_WHEEL_SEPARATION_M, "stop_latency_s": 0.0}
#: Typical size of each parameter, for the least-squares scaling and the identifiability test.
SCALE = {"radius_mean_m": 0.001, "radius_difference_m": 0.001, "wheel_separation_m": 0.01,
         "stop_latency_s": 0.1}

CSV_REQUIRED = ("test", "commanded_m", "speed_mps", "measured_m")
CSV_OPTIONAL = ("turn_radps", "lateral_m", "left_wheel_rad", "right_wheel_rad", "note")
TESTS = ("straight", "square")


class CalibrationError(ValueError):
    """Base of the errors of this module; the message says what to fix."""


class DataError(CalibrationError):
    """Malformed measurements: the message names the file, the line and the field."""


class NotIdentifiableError(CalibrationError):
    """The runs cannot determine a requested parameter (too few runs, or none of the right kind)."""


@dataclass
class Run:
    """One measured run (units in the names)."""
    test: str                 # "straight" or "square"
    commanded_m: float        # straight: commanded distance; square: side length
    speed_mps: float          # linear speed of the straight parts
    measured_m: float         # straight: start-to-end distance; square: closing error
    turn_radps: float = 1.0   # square: turn rate of the timed turns
    lateral_m: Optional[float] = None       # straight: sideways offset at the end, + left
    left_wheel_rad: Optional[float] = None  # encoder: total angle of the left wheel
    right_wheel_rad: Optional[float] = None
    source: str = ""          # "file:line", for messages
    note: str = ""


@dataclass
class Fit:
    """Result of a calibration."""
    values: Dict[str, float]        # every parameter of PARAMETERS (fitted or held at nominal)
    fitted: List[str]               # names of the fitted ones
    stderr: Dict[str, float]        # standard error of each fitted parameter
    covariance: np.ndarray          # of the fitted parameters, in the order of `fitted`
    residuals_m: np.ndarray         # measured - predicted, one per observation
    observations: List[str]         # what each residual is ("file:line measured_m", ...)
    residual_scale_m: float         # s: the RMS residual (or the resolution, if larger)
    held: Dict[str, str] = field(default_factory=dict)  # not fitted -> why

    def radii(self):
        """(left, right) wheel radius [m] and the standard error of each."""
        mean, diff = self.values["radius_mean_m"], self.values["radius_difference_m"]
        var = {}
        for name, sign in (("left", -0.5), ("right", 0.5)):
            g = np.array([1.0 if p == "radius_mean_m" else sign if p == "radius_difference_m" else 0.0
                          for p in self.fitted])
            var[name] = float(g @ self.covariance @ g) if len(g) else 0.0
        return ((mean - diff / 2, math.sqrt(var["left"])), (mean + diff / 2, math.sqrt(var["right"])))


# ------------------------------------------------------------------------------------ the model

def _arc(x, y, yaw, distance_m, dyaw_rad):
    """Pose after rolling `distance_m` along a circular arc turning by `dyaw_rad`."""
    if abs(dyaw_rad) < 1e-12:
        return x + distance_m * math.cos(yaw), y + distance_m * math.sin(yaw), yaw
    radius = distance_m / dyaw_rad
    return (x + radius * (math.sin(yaw + dyaw_rad) - math.sin(yaw)),
            y - radius * (math.cos(yaw + dyaw_rad) - math.cos(yaw)), yaw + dyaw_rad)


def straight_motion(values, commanded_m, speed_mps):
    """(wheel angle [rad], rolled distance [m], heading change [rad]) of a straight run."""
    phi = (commanded_m + speed_mps * values["stop_latency_s"]) / NOMINAL_WHEEL_RADIUS_M
    r_left = values["radius_mean_m"] - values["radius_difference_m"] / 2
    r_right = values["radius_mean_m"] + values["radius_difference_m"] / 2
    return phi, (r_left + r_right) / 2 * phi, (r_right - r_left) * phi / values["wheel_separation_m"]


def predict_straight(values, commanded_m, speed_mps):
    """(start-to-end distance [m], sideways offset [m], wheel angle [rad]) of a straight run."""
    phi, distance, dyaw = straight_motion(values, commanded_m, speed_mps)
    x, y, _ = _arc(0.0, 0.0, 0.0, distance, dyaw)
    return math.hypot(x, y), y, phi


def square_path(values, side_m, speed_mps, turn_radps=1.0):
    """Corner positions [(x, y)] of a square (left turns) from (0, 0) heading +x."""
    phi_turn = (math.pi / 2) * NOMINAL_WHEEL_SEPARATION_M / (2 * NOMINAL_WHEEL_RADIUS_M)  # timed: no latency
    r_left = values["radius_mean_m"] - values["radius_difference_m"] / 2
    r_right = values["radius_mean_m"] + values["radius_difference_m"] / 2
    turn_yaw = phi_turn * (r_left + r_right) / values["wheel_separation_m"]
    turn_shift = phi_turn * (r_right - r_left) / 2
    x = y = yaw = 0.0
    points = [(x, y)]
    for _ in range(4):
        _, distance, dyaw = straight_motion(values, side_m, speed_mps)
        x, y, yaw = _arc(x, y, yaw, distance, dyaw)
        x, y, yaw = _arc(x, y, yaw, turn_shift, turn_yaw)
        points.append((x, y))
    return points


def predict_square(values, side_m, speed_mps, turn_radps=1.0):
    """Closing error [m] of a square."""
    x, y = square_path(values, side_m, speed_mps, turn_radps)[-1]
    return math.hypot(x, y)


def predict(values, run: Run):
    """The observations of `run` predicted by the model: {name: value}."""
    if run.test == "straight":
        distance, lateral, phi = predict_straight(values, run.commanded_m, run.speed_mps)
        out = {"measured_m": distance}
        if run.lateral_m is not None:
            out["lateral_m"] = lateral
        if run.left_wheel_rad is not None:
            out["left_wheel_rad"] = phi
        if run.right_wheel_rad is not None:
            out["right_wheel_rad"] = phi
        return out
    return {"measured_m": predict_square(values, run.commanded_m, run.speed_mps, run.turn_radps)}


# ---------------------------------------------------------------------------------- reading data

def read_runs_csv(path) -> List[Run]:
    """Runs from a CSV file (header line first; '#' lines are comments). DataError names the file,
    line and field of the first problem."""
    try:
        with open(path, newline="") as f:
            lines = f.read().splitlines()
    except OSError as e:
        raise DataError(f"{path}: cannot read: {e.strerror}") from e
    numbered = [(i + 1, line) for i, line in enumerate(lines) if line.strip() and not line.lstrip().startswith("#")]
    if not numbered:
        raise DataError(f"{path}: no header line (expected the columns {', '.join(CSV_REQUIRED)})")
    header_line, header = numbered[0][0], next(csv.reader([numbered[0][1]]))
    header = [h.strip() for h in header]
    for name in header:
        if name not in CSV_REQUIRED + CSV_OPTIONAL:
            raise DataError(f"{path}:{header_line}: unknown column '{name}' "
                            f"(known: {', '.join(CSV_REQUIRED + CSV_OPTIONAL)})")
    for name in CSV_REQUIRED:
        if name not in header:
            raise DataError(f"{path}:{header_line}: missing column '{name}'")
    runs = []
    for line_no, line in numbered[1:]:
        cells = next(csv.reader([line]))
        where = f"{path}:{line_no}"
        if len(cells) != len(header):
            raise DataError(f"{where}: {len(cells)} fields, the header has {len(header)}")
        row = dict(zip(header, (c.strip() for c in cells)))
        runs.append(_run_from_row(row, where))
    if not runs:
        raise DataError(f"{path}: no runs after the header")
    return runs


def _number(row, name, where, required, positive=False):
    text = row.get(name, "")
    if text == "":
        if required:
            raise DataError(f"{where}: field '{name}' is empty")
        return None
    try:
        value = float(text)
    except ValueError:
        raise DataError(f"{where}: field '{name}': '{text}' is not a number") from None
    if not math.isfinite(value):
        raise DataError(f"{where}: field '{name}': '{text}' is not finite")
    if positive and value <= 0:
        raise DataError(f"{where}: field '{name}': {text} must be > 0")
    return value


def _run_from_row(row, where):
    test = row["test"]
    if test not in TESTS:
        raise DataError(f"{where}: field 'test': '{test}' (expected one of {', '.join(TESTS)})")
    run = Run(test=test, commanded_m=_number(row, "commanded_m", where, True, positive=True),
              speed_mps=_number(row, "speed_mps", where, True, positive=True),
              measured_m=_number(row, "measured_m", where, True), source=where, note=row.get("note", ""))
    if run.measured_m < 0:
        raise DataError(f"{where}: field 'measured_m': {run.measured_m} must be >= 0")
    if test == "square":
        run.turn_radps = _number(row, "turn_radps", where, True, positive=True)
        for name in ("lateral_m", "left_wheel_rad", "right_wheel_rad"):
            if row.get(name, ""):
                raise DataError(f"{where}: field '{name}' is for straight runs only")
    else:
        run.lateral_m = _number(row, "lateral_m", where, False)
        run.left_wheel_rad = _number(row, "left_wheel_rad", where, False)
        run.right_wheel_rad = _number(row, "right_wheel_rad", where, False)
    return run


def write_runs_csv(path, runs: Sequence[Run], comments=()):
    """Writes runs in the format read_runs_csv reads."""
    with open(path, "w", newline="") as f:
        for c in comments:
            f.write(f"# {c}\n")
        w = csv.writer(f, lineterminator="\n")
        w.writerow(CSV_REQUIRED + CSV_OPTIONAL)
        for r in runs:
            def opt(v):
                return "" if v is None else repr(float(v))
            w.writerow([r.test, repr(r.commanded_m), repr(r.speed_mps), repr(r.measured_m),
                        repr(r.turn_radps) if r.test == "square" else "", opt(r.lateral_m),
                        opt(r.left_wheel_rad), opt(r.right_wheel_rad), r.note])


# ------------------------------------------------------------------------------------- fitting

def identifiable_parameters(runs: Sequence[Run]) -> Dict[str, str]:
    """Parameters these runs can determine -> the kind of run that determines each."""
    straight = [r for r in runs if r.test == "straight"]
    out = {}
    if straight:
        out["radius_mean_m"] = "straight runs (distance)"
        # overshoot = speed * latency: a separate offset needs two commanded distances.
        if len({round(r.commanded_m, 6) for r in straight}) >= 2:
            out["stop_latency_s"] = "straight runs at two or more commanded distances"
        elif any(r.left_wheel_rad is not None or r.right_wheel_rad is not None for r in straight):
            out["stop_latency_s"] = "wheel encoder totals of straight runs"
        if any(r.lateral_m is not None for r in straight):
            out["radius_difference_m"] = "sideways offsets of straight runs"
    if any(r.test == "square" for r in runs):
        out["wheel_separation_m"] = "squares (closing error)"
    return out


def why_not(name: str) -> str:
    return {"radius_mean_m": "it needs straight runs",
            "stop_latency_s": "it needs straight runs at two or more commanded distances, or wheel encoder "
                              "totals (the overshoot is otherwise indistinguishable from the distance scale)",
            "radius_difference_m": "it needs the sideways offset (lateral_m) of straight runs; distances "
                                   "and closing errors do not separate it from the wheel separation",
            "wheel_separation_m": "it needs turning runs (squares); straight runs do not depend on it"}[name]


def _observations(runs):
    obs = []
    for run in runs:
        for name, value in (("measured_m", run.measured_m), ("lateral_m", run.lateral_m),
                            ("left_wheel_rad", run.left_wheel_rad), ("right_wheel_rad", run.right_wheel_rad)):
            if value is not None:
                # wheel angles [rad] weighted to metres with the nominal radius
                weight = NOMINAL_WHEEL_RADIUS_M if name.endswith("_rad") else 1.0
                obs.append((run, name, value, weight))
    return obs


def fit(runs: Sequence[Run], parameters: Optional[Sequence[str]] = None, fixed: Optional[Dict[str, float]] = None,
        resolution_m: float = DEFAULT_RESOLUTION_M) -> Fit:
    """Least-squares fit of `parameters` (default: every parameter the runs identify) to the runs;
    the others are held at `fixed` or nominal. NotIdentifiableError if a requested parameter
    cannot be determined by these runs, or if there are not more observations than parameters."""
    if not runs:
        raise NotIdentifiableError("no runs to fit")
    can = identifiable_parameters(runs)
    if parameters is None:
        parameters = [p for p in PARAMETERS if p in can]
    for p in parameters:
        if p not in PARAMETERS:
            raise CalibrationError(f"unknown parameter '{p}' (known: {', '.join(PARAMETERS)})")
        if p not in can:
            raise NotIdentifiableError(f"{p} cannot be identified from these runs: {why_not(p)}")
    base = dict(NOMINAL)
    base.update(fixed or {})
    obs = _observations(runs)
    if len(obs) <= len(parameters):
        raise NotIdentifiableError(
            f"too few runs to identify {', '.join(parameters)}: {len(obs)} measurements for {len(parameters)} "
            f"parameters (at least {len(parameters) + 1} are needed to estimate the uncertainty too)")
    scale = np.array([SCALE[p] for p in parameters])

    def values_of(z):
        v = dict(base)
        v.update({p: base[p] + zi * s for p, zi, s in zip(parameters, z, scale)})
        return v

    def residuals(z):
        v = values_of(z)
        cache, out = {}, []
        for run, name, value, weight in obs:
            if id(run) not in cache:
                cache[id(run)] = predict(v, run)
            out.append((value - cache[id(run)][name]) * weight)
        return np.array(out)

    # Closing errors are |.|: start from a point where the square does not close exactly.
    result = least_squares(residuals, np.zeros(len(parameters)), method="lm", x_scale=1.0)
    jac = result.jac / scale  # d residual / d parameter (physical units)
    _, sv, _ = np.linalg.svd(result.jac, full_matrices=False)
    if len(sv) and sv[-1] < 1e-9 * max(sv[0], 1e-300):
        raise NotIdentifiableError(f"the runs do not determine {', '.join(parameters)} together (the Jacobian is "
                                   f"singular: singular values {', '.join(f'{s:.3g}' for s in sv)})")
    dof = len(obs) - len(parameters)
    rms = math.sqrt(float(result.fun @ result.fun) / dof)
    s = max(rms, resolution_m)
    covariance = s * s * np.linalg.inv(jac.T @ jac)
    values = values_of(result.x)
    held = {p: why_not(p) if p not in can else "held by request" for p in PARAMETERS if p not in parameters}
    return Fit(values=values, fitted=list(parameters),
               stderr={p: math.sqrt(covariance[i, i]) for i, p in enumerate(parameters)},
               covariance=covariance, residuals_m=result.fun,
               observations=[f"{run.source} {name}" for run, name, _, _ in obs], residual_scale_m=s, held=held)


def prediction_stderr(result: Fit, predict_fn, h_rel=1e-4) -> float:
    """Standard error of a scalar prediction predict_fn(values) from the fit's covariance (delta method)."""
    grad = []
    for p in result.fitted:
        h = SCALE[p] * h_rel
        up, down = dict(result.values), dict(result.values)
        up[p] += h
        down[p] -= h
        grad.append((predict_fn(up) - predict_fn(down)) / (2 * h))
    g = np.array(grad)
    return math.sqrt(float(g @ result.covariance @ g)) if len(g) else 0.0


# ---------------------------------------------------------------------------------- the YAML file

def calibration_dict(result: Fit, data_source: str) -> dict:
    """What the robot xacro reads (conde.urdf.xacro, arg calibration): the effective geometry,
    plus the fit's uncertainty and provenance for people."""
    (r_left, se_left), (r_right, se_right) = result.radii()
    return {
        "wheel_radius_left_m": float(r_left),
        "wheel_radius_right_m": float(r_right),
        "wheel_separation_m": float(result.values["wheel_separation_m"]),
        "stop_latency_s": float(result.values["stop_latency_s"]),
        "fit": {
            "data": data_source,
            "fitted": list(result.fitted),
            "stderr": {"wheel_radius_left_m": se_left, "wheel_radius_right_m": se_right,
                       **{p: float(result.stderr[p]) for p in result.fitted
                          if p in ("wheel_separation_m", "stop_latency_s")}},
            "held_at_nominal": {p: why for p, why in result.held.items()},
            "residual_rms_m": float(result.residual_scale_m),
        },
    }
