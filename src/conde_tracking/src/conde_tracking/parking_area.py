"""The bay-parking area seen by Conde's two ground cameras: the white lines across the bays (the
bays' borders and the dashed divider between them), located in base_footprint [m], and which of
the bays between them holds a box.  Pure numpy + OpenCV, no ROS.

The bay-parking area lies to the right of the east lane: a border line along the road, and lines
across it (perpendicular to the road) that close the bays.  Per image pair:
  1. white marking pixels (lane_measurement.line_mask, any light) are put on the ground
     (GroundMap) and kept in the band to the right of the lane (band_y_m) and ahead (band_x_m);
  2. for each candidate angle of a line across the road (the robot's heading error,
     within max_angle_rad), the points are binned by their position u = x + y tan(angle) along
     the road; in each bin the points' lateral positions are chained (gaps up to max_gap_m: the
     divider is dashed) and the longest chain is the line's visible length;
  3. a line is a chain at least min_length_m long (the letters "P" painted in the bays are
     0.5 m long, the bays' lines about 0.9-1.05 m), the strongest of any within min_separation_m;
     it is reported by its x at its road end (largest y: where a robot turning in crosses it); a
     chain counts only if it begins at the road side, unbroken for near_solid_m (bay lines meet
     the border along the road, the "P" stands 0.19 m off it);
  4. bays are pairs of neighbouring lines a bay width apart (or twice: two bays); a bay is
     occupied when a box seen by conde_tracking.obstacles right of the road begins within a bay
     width before its centre (conde_common.bay_pairing, the rule the decision shares).

Which line is which (border or divider) and the bays' positions along the road are the
decision's business (conde_decision.parking), which accumulates sightings while it drives.
"""
import math
from dataclasses import dataclass
from typing import List, Sequence, Tuple

import numpy as np
from conde_common.bay_pairing import BAY_WIDTH_M, pair_bays

from conde_tracking.ipm import GroundMap
from conde_tracking.lane_measurement import LaneConfig
from conde_tracking.obstacles import BOX, Detection
from conde_tracking.parallel_bay import white_ground_points


@dataclass(frozen=True)
class ParkingAreaConfig:
    band_x_m: Tuple[float, float] = (0.25, 1.8)  # look this far ahead of base_footprint [m]
    band_y_m: Tuple[float, float] = (-2.0, -0.55)  # ... in this lateral band (right of the lane) [m]
    max_angle_rad: float = 0.2  # lines across the road within this angle of base_footprint's y axis [rad]
    angle_step_rad: float = 0.0333
    bin_m: float = 0.02  # bin width along the road [m]
    line_halfwidth_m: float = 0.04  # points within this of a bin's centre belong to its line [m]
    lateral_cell_m: float = 0.03  # lateral resolution of the chains [m]
    max_gap_m: float = 0.25  # a chain bridges gaps up to this (the divider's dashes: 0.148 m, seen 0.17-0.2) [m]
    solid_gap_m: float = 0.06  # ... and is unbroken with gaps up to this [m]
    near_solid_m: float = 0.2  # a bay line's chain is unbroken for this long from its road-side end [m]
    near_end_y_m: float = -0.92  # ... which is at least this far left (the bays' border along the road) [m]
    min_length_m: float = 0.7  # shorter chains are not a bay line [m]
    min_fill: float = 0.6  # a bay line's chain is painted for at least this share of min_length_m
    min_separation_m: float = 0.15  # lines closer than this along the road (at y = -1 m) are one [m]

    def check(self) -> "ParkingAreaConfig":
        """Returns self if usable, else raises ValueError naming the field."""
        for name in ("band_x_m", "band_y_m"):
            lo, hi = getattr(self, name)
            if not lo < hi:
                raise ValueError("%s: expected (low, high) with low < high, got %r" % (name, getattr(self, name)))
        for name in ("max_angle_rad", "angle_step_rad", "bin_m", "line_halfwidth_m", "lateral_cell_m", "max_gap_m",
                     "solid_gap_m", "near_solid_m", "min_length_m", "min_fill", "min_separation_m"):
            if not getattr(self, name) > 0:
                raise ValueError("%s: must be > 0, got %r" % (name, getattr(self, name)))
        return self


@dataclass(frozen=True)
class BayLine:
    x_m: float  # ahead of base_footprint where the line meets the road side (its largest y) [m]
    angle_rad: float  # its direction from base_footprint's -y axis, + = its far end farther ahead [rad]
    y_near_m: float  # lateral extent of the part seen [m] (y_near_m > y_far_m; both < 0: right)
    y_far_m: float

    @property
    def length_m(self) -> float:
        return self.y_near_m - self.y_far_m

    def x_at(self, y_m: float) -> float:
        """x [m] of the line at lateral y_m."""
        return self.x_m + (y_m - self.y_near_m) * -math.tan(self.angle_rad)


@dataclass(frozen=True)
class Bay:
    near_x_m: float  # its nearer line (x at the road side) [m]
    far_x_m: float  # its farther line [m]
    occupied: bool  # a box lies between its lines

    @property
    def centre_x_m(self) -> float:
        return 0.5 * (self.near_x_m + self.far_x_m)


def _bay_line_chain(cells: np.ndarray, y0_m: float, config: "ParkingAreaConfig") -> Tuple[float, float]:
    """(low, high) lateral extent [m] of the longest chain of occupied lateral cells (sorted indices
    of cells lateral_cell_m wide from y0_m; gaps up to
    max_gap_m) that begins at the road side like a bay line: its road-side end (high y) within
    near_end_y_m and unbroken (gaps up to solid_gap_m) for at least near_solid_m; (0, 0) if none.
    A bay line meets the border along the road; the "P" painted in a bay stands 0.19 m off it."""
    c = config
    if len(cells) == 0:
        return 0.0, 0.0
    gaps_m = np.diff(cells) * c.lateral_cell_m - c.lateral_cell_m
    # solid runs (gaps up to solid_gap_m), each a possible road-side end of a line
    breaks = np.flatnonzero(gaps_m > c.solid_gap_m)
    starts = np.concatenate([[0], breaks + 1])
    ends = np.concatenate([breaks, [len(cells) - 1]])
    best = (0.0, 0.0)
    for a, b in zip(starts, ends):
        high = y0_m + (cells[b] + 1) * c.lateral_cell_m
        if high < c.near_end_y_m or high - (y0_m + cells[a] * c.lateral_cell_m) < c.near_solid_m:
            continue
        k = a  # extend away from the road across gaps up to max_gap_m
        while k > 0 and gaps_m[k - 1] <= c.max_gap_m:
            k -= 1
        low = y0_m + cells[k] * c.lateral_cell_m
        if high - low > best[1] - best[0]:
            best = (float(low), float(high))
    return best


class ParkingAreaDetector:
    """Finds the bay lines in image pairs of calibrated cameras (GroundMap per camera, same order)."""

    def __init__(self, ground_maps: Sequence[GroundMap], config: ParkingAreaConfig = ParkingAreaConfig(),
                 lane_config: LaneConfig = LaneConfig()):
        self.ground_maps = list(ground_maps)
        self.config = config.check()
        self.lane_config = lane_config

    def ground_points(self, images) -> np.ndarray:
        """White marking points (N, 2) [m] in the band, from every camera."""
        return self.in_band(white_ground_points(images, self.ground_maps, self.lane_config))

    def in_band(self, xy: np.ndarray) -> np.ndarray:
        """The points (N, 2) [m] in the band."""
        c = self.config
        keep = ((xy[:, 0] >= c.band_x_m[0]) & (xy[:, 0] <= c.band_x_m[1])
                & (xy[:, 1] >= c.band_y_m[0]) & (xy[:, 1] <= c.band_y_m[1]))
        return xy[keep]

    def lines_in(self, xy: np.ndarray) -> List[BayLine]:
        """The bay lines among ground points (N, 2) [m], nearest first."""
        c = self.config
        candidates = []  # (length, u, angle, y_low, y_high)
        if len(xy) == 0:
            return []
        n_angles = int(round(c.max_angle_rad / c.angle_step_rad))
        cell = np.floor((xy[:, 1] - c.band_y_m[0]) / c.lateral_cell_m).astype(int).clip(0)
        n_cells = cell.max() + 1
        for angle in np.arange(-n_angles, n_angles + 1) * c.angle_step_rad:
            # a line at `angle` from the -y axis: x = u - y tan(angle) (far end, y more negative, farther ahead)
            u = xy[:, 0] + xy[:, 1] * math.tan(angle)
            # occupancy of lateral cells per bin (points within line_halfwidth_m of its centre); only
            # bins with cells for min_fill of min_length_m are searched for a chain
            index = np.floor((u - u.min()) / c.bin_m).astype(int)
            reach = int(math.ceil(c.line_halfwidth_m / c.bin_m))
            occupied = np.zeros((index.max() + 1 + 2 * reach, n_cells), bool)
            for shift in range(-reach, reach + 1):
                occupied[index + reach + shift, cell] = True
            for b in np.flatnonzero(occupied.sum(axis=1) * c.lateral_cell_m >= c.min_fill * c.min_length_m):
                lo, hi = _bay_line_chain(np.flatnonzero(occupied[b]), c.band_y_m[0], c)
                if hi - lo >= c.min_length_m:
                    centre = u.min() + (b - reach + 0.5) * c.bin_m
                    sel = (np.abs(u - centre) <= (reach + 0.5) * c.bin_m) & (xy[:, 1] >= lo) & (xy[:, 1] <= hi)
                    candidates.append((hi - lo, int(sel.sum()), float(np.median(u[sel])), float(angle), lo, hi))
        lines: List[BayLine] = []
        kept_u: List[float] = []
        # the true angle puts the most points within line_halfwidth_m of the line
        for length, _, u0, angle, lo, hi in sorted(candidates, key=lambda t: (-t[1], -t[0])):
            x_ref = u0 + math.tan(angle)  # x at y = -1 m
            if any(abs(x_ref - k) < c.min_separation_m for k in kept_u):
                continue
            kept_u.append(x_ref)
            lines.append(BayLine(u0 - hi * math.tan(angle), angle, hi, lo))
        return sorted(lines, key=lambda line: line.x_m)

    def detect(self, images) -> List[BayLine]:
        """The bay lines in one image per ground map, nearest first."""
        return self.lines_in(self.ground_points(images))


def bays_between(lines: Sequence[BayLine], boxes: Sequence[Detection],
                 width_m: Tuple[float, float] = BAY_WIDTH_M) -> List[Bay]:
    """The bays enclosed by neighbouring lines (nearest first) and which hold a box standing right
    of the road side (below the lines' y_near_m): conde_common.bay_pairing's rule, the one
    conde_decision applies to its sightings along the road."""
    side_y = max((line.y_near_m for line in lines), default=0.0)
    near_ends = [d.near_x_m for d in boxes if d.kind == BOX and d.y_centre_m < side_y]
    return [Bay(a, b, occupied) for a, b, occupied in pair_bays([line.x_m for line in lines], near_ends, width_m)]
