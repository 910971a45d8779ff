"""Evaluation of an autonomous run on the competition track from the ground-truth path: laps and
lap times, lane keeping, and a plot of the path over the track. Pure Python (numpy, matplotlib).

Frames and units: world frame of the track (x east, y north), metres, seconds."""
import math

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
