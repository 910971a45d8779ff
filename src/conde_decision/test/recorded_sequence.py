"""Replays a recorded input sequence of conde_decision (fixtures/*_sequence.csv, written by
fixtures/make_lane_sequence.py from a rosbag of a closed-loop run) through DecisionLogic, as the
node does: the signals and odometry stamped before a lane measurement first, then the measurement.
Pure Python; shared by the decision tests."""

import csv
import math
import os
from types import SimpleNamespace

FIXTURES_DIR = os.path.join(os.path.dirname(os.path.abspath(__file__)), "fixtures")
INT_FIELDS = ("signal", "lane_index", "crosswalk_seen")
STRING_FIELDS = ("kind", "command_lane")


def load(name):
    """The rows of fixtures/<name>: dicts of floats (ints for INT_FIELDS, strings for STRING_FIELDS), empty
    cells left out."""
    with open(os.path.join(FIXTURES_DIR, name)) as f:
        return [{k: (int(v) if k in INT_FIELDS else v if k in STRING_FIELDS else float(v))
                 for k, v in row.items() if v != ""}
                for row in csv.DictReader(f)]


def lane_of(row):
    """A LaneMeasurement-like object of a lane row (no obstacles, no bay lines)."""
    lane = SimpleNamespace(obstacle_kinds=(), obstacle_distances_m=(), obstacle_lane_y_min_m=(),
                           obstacle_lane_y_max_m=(), obstacle_y_max_m=(), bay_line_distances_m=())
    for name in ("lateral_offset_m", "heading_error_rad", "confidence", "crosswalk_distance_m", "right_line_end_m",
                 "left_line_end_m", "far_left_line_end_m", "lane_spacing_m"):
        setattr(lane, name, row.get(name, math.nan))
    lane.crosswalk_seen = bool(row.get("crosswalk_seen", 0))
    lane.lane_index = row.get("lane_index", -1)
    return lane


def replay(logic, rows, stop=lambda t_s, out: False, notes=None):
    """Feeds the rows to logic; returns [(t_s, row, DecisionOutput)] of the lane rows, up to the
    first for which stop(t_s, out) is true; the logic's notes are added to the list `notes`."""
    outputs = []
    for row in rows:
        if row["kind"] == "signal":
            logic.on_signal(row["signal"], row["confidence"], row.get("t_s"))
            continue
        logic.on_odometry(row["yaw_rad"], row["odom_path_m"])
        out = logic.on_lane(lane_of(row), row["t_s"])
        if notes is not None:
            notes.extend(logic.notes)
        outputs.append((row["t_s"], row, out))
        if stop(row["t_s"], out):
            break
    return outputs
