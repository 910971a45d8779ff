"""The seed paper's odometry test, as data and arithmetic (no ROS).

Straight runs of 1, 2 and 3 m and 1 m squares at 0.3 and 0.5 m/s with 1 rad/s turns. A scenario
is a list of segments (duration [s], linear speed [m/s], angular speed [rad/s]); the result of a
run is the ground-truth and odometry poses (x [m], y [m], yaw [rad]) at its start and end.

Two ways to drive a straight segment: timed (duration at the speed, the default), or *by distance
reference* (`by_distance`), the paper's protocol: at the speed until the robot's own odometry
(/odom) says the segment's length (duration x speed) is done, then stop. Turns are always timed.
"""
import math
from dataclasses import dataclass
from typing import List, Tuple

from conde_common.angles import wrap_rad

Segment = Tuple[float, float, float]  # duration_s, linear_mps, angular_radps

STRAIGHT_SPEED_MPS = 0.3
TURN_RATE_RADPS = 1.0
SQUARE_SIDE_M = 1.0


@dataclass
class Scenario:
    name: str
    kind: str             # "straight" or "square"
    commanded_m: float    # commanded path length (straight) or perimeter (square)
    segments: List[Segment]
    by_distance: bool = False  # straight segments end when /odom reports their length
    speed_mps: float = STRAIGHT_SPEED_MPS


def straight(distance_m: float, speed_mps: float = STRAIGHT_SPEED_MPS, by_distance: bool = False) -> Scenario:
    return Scenario(f"straight {distance_m:g} m at {speed_mps:g} m/s", "straight", distance_m,
                    [(distance_m / speed_mps, speed_mps, 0.0)], by_distance, speed_mps)


def square(speed_mps: float, side_m: float = SQUARE_SIDE_M, turn_radps: float = TURN_RATE_RADPS,
           by_distance: bool = False) -> Scenario:
    side = (side_m / speed_mps, speed_mps, 0.0)
    turn = (math.pi / 2 / turn_radps, 0.0, turn_radps)
    return Scenario(f"square {side_m:g} m at {speed_mps:g} m/s", "square", 4 * side_m, [side, turn] * 4,
                    by_distance, speed_mps)


def default_scenarios() -> List[Scenario]:
    return [straight(1.0), straight(2.0), straight(3.0), square(0.3), square(0.5)]


PAPER_DISTANCES_M = (1.0, 2.0, 3.0)
PAPER_REPEATS = 5
PAPER_SQUARE_SPEEDS_MPS = (0.3, 0.5)
PAPER_SQUARES = 4  # per speed


def paper_scenarios(distances_m=PAPER_DISTANCES_M, repeats: int = PAPER_REPEATS, squares: int = PAPER_SQUARES,
                    square_speeds_mps=PAPER_SQUARE_SPEEDS_MPS) -> List[Scenario]:
    """The paper's protocol, driven by distance reference: `repeats` straight runs per distance
    (at STRAIGHT_SPEED_MPS), then `squares` 1 m squares per speed (1 rad/s timed turns)."""
    out = [straight(d, by_distance=True) for d in distances_m for _ in range(repeats)]
    out += [square(v, by_distance=True) for v in square_speeds_mps for _ in range(squares)]
    return out


def relative_pose(start, end):
    """`end` (x, y, yaw) expressed in the frame of `start`."""
    dx, dy = end[0] - start[0], end[1] - start[1]
    c, s = math.cos(start[2]), math.sin(start[2])
    return (c * dx + s * dy, -s * dx + c * dy, wrap_rad(end[2] - start[2]))


def evaluate(scenario: Scenario, truth_start, truth_end, odom_start, odom_end) -> dict:
    """Travelled distance and closing error by ground truth, and what odometry believed."""
    truth = relative_pose(truth_start, truth_end)
    odom = relative_pose(odom_start, odom_end)
    row = {"scenario": scenario.name, "kind": scenario.kind, "commanded_m": scenario.commanded_m,
           "speed_mps": scenario.speed_mps, "by_distance": scenario.by_distance}
    if scenario.kind == "straight":
        row["travelled_m"] = math.hypot(truth[0], truth[1])
        row["error_pct"] = 100.0 * (row["travelled_m"] - scenario.commanded_m) / scenario.commanded_m
        row["lateral_m"] = truth[1]  # sideways offset at the end, + left
        row["odometry_m"] = math.hypot(odom[0], odom[1])
        row["heading_error_deg"] = math.degrees(truth[2])
    else:
        row["closing_error_m"] = math.hypot(truth[0], truth[1])
        row["odometry_closing_m"] = math.hypot(odom[0], odom[1])
        row["heading_error_deg"] = math.degrees(truth[2])
    row["odometry_drift_m"] = math.hypot(odom[0] - truth[0], odom[1] - truth[1])
    return row


def format_table(rows_by_engine: dict) -> str:
    """Markdown table: one line per engine and scenario."""
    lines = ["| engine | test | commanded | travelled (ground truth) | error | closing error (ground truth) "
             "| final heading error | odometry drift |",
             "|---|---|---|---|---|---|---|---|"]
    for engine, rows in rows_by_engine.items():
        for r in rows:
            if r["kind"] == "straight":
                travelled = f"{r['travelled_m']:.4f} m"
                error = f"{r['error_pct']:+.2f} %"
                closing = "-"
            else:
                travelled, error = "-", "-"
                closing = f"{r['closing_error_m'] * 100:.2f} cm"
            lines.append(f"| {engine} | {r['scenario']} | {r['commanded_m']:.3f} m | {travelled} | {error} | {closing} "
                         f"| {r['heading_error_deg']:+.2f} deg | {r['odometry_drift_m'] * 100:.2f} cm |")
    return "\n".join(lines)
