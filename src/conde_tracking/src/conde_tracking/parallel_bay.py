"""The parallel-parking bay seen by Conde's two ground cameras: where its straight part begins
along the road, located in base_footprint [m].  Pure numpy, no ROS.

The parallel bay lies to the right of the lane: a line along the road (its outer line, 1.232 m
right of the lane's centre on the competition track) between two end lines slanted at 45 degrees
that join the road's edge line.  Per image pair:
  1. white marking points (lane_measurement.line_mask, any light) are put on the ground and
     measured from the lane's centre curve (the lane fit of the same frame): a line along the
     road has one lateral position in that frame, whatever the robot's heading;
  2. the outer line is the most populated lateral position in band_lateral_m (bins of bin_m,
     at least min_points points within line_halfwidth_m of it);
  3. its points' positions along x are chained (gaps up to max_gap_m); the first chain at least
     min_length_m long begins where the bay's straight part begins, less corner_lead_m (the
     slanted end line enters the line's band that much before the corner);
  4. that beginning counts only if the cameras see the ground before it (else the view cuts the
     line) and no box right of the lane lies nearer (else the box hides the line's start).

The boxes in the bay (P2) and their ends come from conde_tracking.obstacles (near_x_m, far_x_m);
the free stretch between them and where to park are the decision's business
(conde_decision.parking.ParallelGapFinder), which accumulates sightings while it drives.
"""
from dataclasses import dataclass
from typing import Sequence, Tuple

import numpy as np

from conde_tracking.ipm import GroundMap
from conde_tracking.lane_measurement import LaneConfig, line_mask
from conde_tracking.obstacles import BOX, Detection


@dataclass(frozen=True)
class ParallelBayConfig:
    band_lateral_m: Tuple[float, float] = (-1.6, -0.95)  # the outer line, from the lane's centre (+ = left) [m]
    bin_m: float = 0.02  # lateral bins of the search [m]
    line_halfwidth_m: float = 0.04  # points within this of the line's lateral position belong to it [m]
    min_points: int = 15  # a line has at least this many points
    max_gap_m: float = 0.1  # its points chain across gaps up to this along x [m]
    min_length_m: float = 0.3  # a chain at least this long is the line [m]
    corner_lead_m: float = 0.06  # the chain begins this far before the corner (the slanted end line) [m]
    view_check_m: float = 0.1  # the ground this far before the line's start must be in view [m]
    view_cell_m: float = 0.05  # resolution of the map of the ground in view [m]
    box_side_m: float = -0.45  # boxes whose left edge is right of this (from the lane centre) are off the road [m]

    def check(self) -> "ParallelBayConfig":
        """Returns self if usable, else raises ValueError naming the field."""
        lo, hi = self.band_lateral_m
        if not lo < hi:
            raise ValueError("band_lateral_m: expected (low, high) with low < high, got %r" % (self.band_lateral_m,))
        for name in ("bin_m", "line_halfwidth_m", "min_points", "max_gap_m", "min_length_m", "view_check_m",
                     "view_cell_m"):
            if not getattr(self, name) > 0:
                raise ValueError("%s: must be > 0, got %r" % (name, getattr(self, name)))
        return self


def white_ground_points(images, ground_maps: Sequence[GroundMap], lane_config: LaneConfig = LaneConfig()) -> np.ndarray:
    """White marking points (N, 2) [m] in base_footprint, from every camera."""
    pts = [gm.points(line_mask(image, lane_config)) for image, gm in zip(images, ground_maps)]
    return np.concatenate(pts) if pts else np.zeros((0, 2))


def lateral_from_lane(xy: np.ndarray, centre_coeffs) -> np.ndarray:
    """y [m] of points (N, 2) from the lane's centre curve y = c0 + c1 x + c2 x^2, + = left."""
    c0, c1, c2 = (float(v) for v in centre_coeffs)
    x = xy[:, 0]
    return xy[:, 1] - (c0 + c1 * x + c2 * x * x)


class ParallelBayDetector:
    """Finds where the parallel bay's straight part begins, in image pairs of calibrated cameras
    (GroundMap per camera, same order)."""

    def __init__(self, ground_maps: Sequence[GroundMap], config: ParallelBayConfig = ParallelBayConfig(),
                 lane_config: LaneConfig = LaneConfig()):
        self.ground_maps = list(ground_maps)
        self.config = config.check()
        self.lane_config = lane_config
        # the ground the cameras see, as a set of view_cell_m cells (never changes)
        seen = [gm.xy_m.reshape(-1, 2) for gm in self.ground_maps]
        seen = np.concatenate(seen) if seen else np.zeros((0, 2))
        seen = seen[np.isfinite(seen[:, 0])]
        self._seen_cells = set(map(tuple, np.floor(seen / config.view_cell_m).astype(int)))

    def in_view(self, x_m: float, y_m: float) -> bool:
        """Whether the cameras see the ground at (x, y) in base_footprint [m]."""
        return (int(np.floor(x_m / self.config.view_cell_m)), int(np.floor(y_m / self.config.view_cell_m))) \
            in self._seen_cells

    def start_in(self, xy: np.ndarray, centre_coeffs, boxes: Sequence[Detection] = ()) -> float:
        """x [m] ahead of base_footprint where the bay's straight part begins, from white ground
        points (N, 2) [m] and the lane's centre curve (LaneResult.centre_coeffs); NaN when not
        seen (no lane fit, no outer line, its start hidden or out of view)."""
        c = self.config
        if centre_coeffs is None or len(xy) == 0:
            return float("nan")
        lateral = lateral_from_lane(xy, centre_coeffs)
        lo, hi = c.band_lateral_m
        band = (lateral >= lo) & (lateral <= hi) & (xy[:, 0] > 0.0)
        if np.count_nonzero(band) < c.min_points:
            return float("nan")
        counts, edges = np.histogram(lateral[band], bins=np.arange(lo, hi + c.bin_m, c.bin_m))
        # the line's position: the mean of the points within line_halfwidth_m of the fullest bin
        peak = edges[np.argmax(counts)] + 0.5 * c.bin_m
        near = band & (np.abs(lateral - peak) <= c.line_halfwidth_m)
        if np.count_nonzero(near) < c.min_points:
            return float("nan")
        line_y = float(np.mean(lateral[near]))
        on_line = band & (np.abs(lateral - line_y) <= c.line_halfwidth_m)
        x = np.sort(xy[on_line, 0])
        breaks = np.flatnonzero(np.diff(x) > c.max_gap_m)
        starts = np.concatenate([[0], breaks + 1])
        ends = np.concatenate([breaks, [len(x) - 1]])
        long_enough = [(x[a], x[b]) for a, b in zip(starts, ends) if x[b] - x[a] >= c.min_length_m]
        if not long_enough:
            return float("nan")
        start = float(long_enough[0][0])
        # the ground before the start in view, on the line (else the view cuts it there)
        x_before = start - c.view_check_m
        c0, c1, c2 = (float(v) for v in centre_coeffs)
        if not self.in_view(x_before, c0 + c1 * x_before + c2 * x_before ** 2 + line_y):
            return float("nan")
        # a box off the road nearer than the start hides the line's real start behind it
        for d in boxes:
            if d.kind == BOX and d.near_x_m < start and d.y_max_m - (c0 + c1 * d.near_x_m + c2 * d.near_x_m ** 2) \
                    < c.box_side_m:
                return float("nan")
        return start + c.corner_lead_m

    def detect(self, images, centre_coeffs, boxes: Sequence[Detection] = ()) -> float:
        """start_in for one image per ground map."""
        return self.start_in(white_ground_points(images, self.ground_maps, self.lane_config), centre_coeffs, boxes)
