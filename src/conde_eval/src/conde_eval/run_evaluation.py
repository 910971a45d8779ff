"""Evaluation of an autonomous run on the competition track from the ground-truth path: laps and
lap times, lane keeping, standstills, and a plot of the path over the track. Pure Python (numpy,
matplotlib).

Frames and units: world frame of the track (x east, y north), metres, seconds."""
import math
from dataclasses import dataclass

import numpy as np

from conde_worlds import track_geometry as tg

#: Laps end where the robot crosses this line northbound in the east lane: 0.21 m before the
#: crosswalk's near edge (y = -0.34), behind the start pose (y = -0.33) and the spot where the
#: robot stops before the crosswalk at the end of the trial.  The first lap starts when the robot
#: first moves.
START_LINE_Y_M = -0.55
MOTION_M = 0.02  # the robot has started once it is this far from where it stood [m]
#: Half of the clear lane width: the robot's base_footprint stays in its lane while its distance
#: to the nearest lane centre is below this.
LANE_HALF_WIDTH_M = tg.LANE_WIDTH / 2.0


class LapTimer:
    """Counts laps from ground-truth positions fed in time order."""

    def __init__(self):
        self.crossings_s = []   # sim times of northbound crossings of the start line, east lane
        self.motion_start_s = None  # when the robot first moved
        self._first = None      # (x, y) where it stood
        self._last = None       # (t, x, y)
        self.top_speed_mps = 0.0

    def feed(self, t_s, x_m, y_m):
        if self._first is None:
            self._first = (x_m, y_m)
        if self.motion_start_s is None and math.hypot(x_m - self._first[0], y_m - self._first[1]) > MOTION_M:
            self.motion_start_s = self._last[0] if self._last is not None else t_s
        if self._last is not None:
            t0, x0, y0 = self._last
            if t_s > t0:
                self.top_speed_mps = max(self.top_speed_mps, math.hypot(x_m - x0, y_m - y0) / (t_s - t0))
            if y0 < START_LINE_Y_M <= y_m and x_m > tg.X_REF:
                # Interpolate the crossing time.
                self.crossings_s.append(t0 + (t_s - t0) * (START_LINE_Y_M - y0) / (y_m - y0))
        self._last = (t_s, x_m, y_m)

    @property
    def laps_s(self):
        """Duration of each completed lap: the first from the first motion (unless the robot
        started behind the line and crossed it within a second), then line to line."""
        marks = list(self.crossings_s)
        if self.motion_start_s is not None and not (marks and marks[0] - self.motion_start_s < 1.0):
            marks.insert(0, self.motion_start_s)
        return [b - a for a, b in zip(marks, marks[1:])]


def lane_keeping(xy):
    """Lane keeping along a path of world points (N, 2): the nearest lane centre for each point.

    Returns a dict: max_offset_m, rms_offset_m (distance of base_footprint to the nearest lane
    centre), in_lane_fraction (share of points closer than LANE_HALF_WIDTH_M), off_road_points
    (points off the road surface), stayed_in_lane (every point in its lane)."""
    xy = np.asarray(xy, dtype=float).reshape(-1, 2)
    if len(xy) == 0:
        return {"max_offset_m": float("nan"), "rms_offset_m": float("nan"), "in_lane_fraction": 0.0,
                "off_road_points": 0, "stayed_in_lane": False}
    where = tg.build_track().locate(xy)
    offset = np.asarray(where["distance"], dtype=float)
    in_lane = offset < LANE_HALF_WIDTH_M
    off_road = int(np.sum(~np.asarray(where["on_road"], dtype=bool)))
    return {"max_offset_m": float(offset.max()), "rms_offset_m": float(np.sqrt(np.mean(offset ** 2))),
            "in_lane_fraction": float(np.mean(in_lane)), "off_road_points": off_road,
            "stayed_in_lane": bool(in_lane.all()) and off_road == 0}


#: Below this ground-truth speed the robot stands still [m/s]: well under any speed it drives at
#: (0.5 m/s cruise), well over the creep of a standing robot in the simulator.
STANDSTILL_SPEED_MPS = 0.01
#: A stop lasts at least this long [s]; shorter pauses (e.g. the speed passing through 0) are not stops.
STANDSTILL_MIN_DURATION_S = 1.0


@dataclass(frozen=True)
class Standstill:
    """An interval in which the robot stood still: from start_s to end_s [s], at the mean position
    (x_m, y_m) [m]; drift_m is the largest distance of a sample of the interval from that position."""

    start_s: float
    end_s: float
    x_m: float
    y_m: float
    drift_m: float

    @property
    def duration_s(self):
        return self.end_s - self.start_s


def standstills(samples, max_speed_mps=STANDSTILL_SPEED_MPS, min_duration_s=STANDSTILL_MIN_DURATION_S):
    """The intervals in which the robot stood still, in time order, from ground-truth samples
    (t_s, x_m, y_m) sorted by time.

    Between two consecutive samples the robot stands if its mean speed is below max_speed_mps;
    a standstill is a run of such steps lasting at least min_duration_s.  Samples with the same
    time as the previous one are skipped.  Raises ValueError on samples out of time order."""
    data = np.asarray(samples, dtype=float).reshape(-1, 3)
    if len(data) and np.any(np.diff(data[:, 0]) < 0.0):
        raise ValueError("standstills: samples must be sorted by time")
    keep = np.concatenate([[True], np.diff(data[:, 0]) > 0.0]) if len(data) else np.zeros(0, dtype=bool)
    data = data[keep]
    t, xy = data[:, 0], data[:, 1:]
    speed_mps = np.hypot(*np.diff(xy, axis=0).T) / np.diff(t) if len(data) > 1 else np.zeros(0)
    found = []
    step = 0
    while step < len(speed_mps):
        if speed_mps[step] >= max_speed_mps:
            step += 1
            continue
        last = step
        while last + 1 < len(speed_mps) and speed_mps[last + 1] < max_speed_mps:
            last += 1
        # Steps step..last stand: samples step..last+1.
        if t[last + 1] - t[step] >= min_duration_s:
            where = xy[step:last + 2]
            mean = where.mean(axis=0)
            drift_m = float(np.max(np.hypot(*(where - mean).T)))
            found.append(Standstill(float(t[step]), float(t[last + 1]), float(mean[0]), float(mean[1]), drift_m))
        step = last + 1
    return found


def plot_path(xy, texture_path, extent_m, out_png, title):
    """Writes a PNG of the path (N, 2) over the track texture; extent_m = (x0, x1, y0, y1)."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.image as mpimg
    import matplotlib.pyplot as plt

    xy = np.asarray(xy, dtype=float).reshape(-1, 2)
    fig, ax = plt.subplots(figsize=(5, 10), dpi=120)
    ax.imshow(mpimg.imread(texture_path), extent=extent_m, origin="upper")
    if len(xy):
        ax.plot(xy[:, 0], xy[:, 1], color="tab:orange", linewidth=1.2, label="driven path (ground truth)")
        ax.plot(xy[0, 0], xy[0, 1], "o", color="tab:green", label="start")
        ax.plot(xy[-1, 0], xy[-1, 1], "s", color="tab:red", label="end")
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    ax.set_title(title, fontsize=9)
    ax.legend(loc="lower left", fontsize=7)
    fig.tight_layout()
    fig.savefig(out_png)
    plt.close(fig)
