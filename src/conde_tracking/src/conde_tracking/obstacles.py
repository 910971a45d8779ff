"""Obstacles (green boxes) and cones (orange) seen by Conde's two ground cameras, located on the
ground in base_footprint [m].  Pure numpy + OpenCV, no ROS.

Pipeline per image pair:
  1. each pixel is classified by colour: green (G well above R and B) or orange (R well above B,
     G between ORANGE_G_SHARE of R); ratios, not absolute levels, so that the darker light of the
     tunnel (a fraction of the brightness) classifies the same (only min_level is absolute);
  2. connected blobs of one colour in each image (OpenCV) of at least min_blob_px pixels;
  3. the flat-ground assumption of the GroundMap (ipm.py) holds only where the object touches
     the floor; pixels higher up on it land farther away along their ray.  The lowest pixel of a
     blob in each image column sees (for a box or a cone seen from above) its outline on the
     floor: those pixels are put on the ground, the near edge is a low percentile of their x and
     the lateral extent their y range;
  4. blobs of the same colour (from both cameras, or two faces of a box) overlapping or touching
     in y (merge_gap_m) with near edges close along x (merge_box_dx_m, merge_cone_dx_m) are one
     object: the union of their extents;
  5. an object wholly to one side shows its side facing the robot's axis (y = 0) down to the
     floor.  With the outline turned into the road's direction (detect's road_direction_rad: a
     box stands along the road), the points within side_band_m of that side (its largest y right
     of the axis, its smallest left of it) run along it to its far end, far_x_m (NaN for an
     object across the axis: its far end is hidden behind it).  Points higher up on the far
     vertical edge land farther out sideways (and farther ahead): the narrow band keeps them out.

Output: Detection(kind, near_x_m, y_min_m, y_max_m, pixels, far_x_m) per object, nearest first.
Which lane an object blocks is the caller's business (conde_decision.avoidance), because that
needs the lane measurement.
"""
import math
from dataclasses import dataclass
from typing import List, Sequence, Tuple

import cv2
import numpy as np

from conde_tracking.ipm import GroundMap
from conde_common.pixel_tables import TableCache, threshold_table

BOX = "box"
CONE = "cone"


@dataclass(frozen=True)
class ObstacleConfig:
    min_level: int = 25  # the dominant channel at least this [0..255] (the tunnel is ~0.35 of daylight)
    green_dominance: float = 0.5  # green: G - max(R, B) >= this share of G
    orange_blue_share: float = 0.4  # orange: B <= this share of R
    orange_green_share: Sequence[float] = (0.08, 0.6)  # orange: G within these shares of R
    min_blob_px: int = 12  # smaller blobs are noise [pixels]
    near_percentile: float = 2.0  # the near edge: this percentile of the blob's ground x
    outline_depth_m: float = 0.35  # outline points this far behind the near edge give the lateral extent [m]
    max_range_m: float = 2.5  # objects farther than this are not reported [m]
    merge_gap_m: float = 0.15  # blobs of one colour this close in y merge ...                        [m]
    merge_box_dx_m: float = 0.5  # ... when their near edges are this close along x: boxes (a face per camera)
    merge_cone_dx_m: float = 0.15  # ... cones (a row of cones 0.45 m apart stays apart)                      [m]
    side_band_m: float = 0.02  # the far end: outline points this close to the side facing the axis [m]

    def check(self) -> "ObstacleConfig":
        """Returns self if usable, else raises ValueError naming the field."""
        for name in ("min_blob_px", "outline_depth_m", "max_range_m", "merge_gap_m", "merge_box_dx_m",
                     "merge_cone_dx_m", "side_band_m"):
            if not getattr(self, name) > 0:
                raise ValueError("%s: must be > 0, got %r" % (name, getattr(self, name)))
        if not 0 <= self.near_percentile <= 50:
            raise ValueError("near_percentile: must be in [0, 50], got %r" % (self.near_percentile,))
        return self


@dataclass(frozen=True)
class Detection:
    kind: str  # BOX or CONE
    near_x_m: float  # distance ahead of base_footprint to the object's nearest point on the floor [m]
    y_min_m: float  # lateral extent of its outline on the floor (the part in view), + = left [m]
    y_max_m: float
    pixels: int  # image pixels that saw it (both cameras)
    # ahead of base_footprint to its far end, along its side facing the robot's axis [m]; NaN: the
    # object lies across the axis (y_min_m < 0 < y_max_m) or the side was not seen
    far_x_m: float = float("nan")

    @property
    def y_centre_m(self) -> float:
        return 0.5 * (self.y_min_m + self.y_max_m)


def _colour_tables(config: ObstacleConfig):
    """colour_masks' tests as thresholds (pixel_tables): (largest max(R, B) of a green pixel per G,
    largest B of an orange pixel per R, least and largest G of an orange pixel per R); None when a
    test is not of that form."""
    c = config
    lo, hi = c.orange_green_share
    tables = (threshold_table(lambda m, g: (g >= c.min_level) & (g - m >= c.green_dominance * g), False),
              threshold_table(lambda b, r: (r >= c.min_level) & (b <= c.orange_blue_share * r), False),
              threshold_table(lambda g, r: g >= lo * r, True),
              threshold_table(lambda g, r: g <= hi * r, False))
    return None if any(t is None for t in tables) else tables


_COLOUR_TABLES = TableCache(_colour_tables)


def colour_masks(image, config: ObstacleConfig):
    """(green, orange) boolean (H, W) masks of an RGB image."""
    img = np.asarray(image)
    if img.ndim != 3 or img.shape[2] < 3:
        empty = np.zeros(img.shape[:2], bool)
        return empty, empty
    tables = _COLOUR_TABLES.get(config) if img.dtype == np.uint8 and img.size else None
    if tables is not None:
        # the tests below, per pixel the same results, as look-ups of thresholds
        green_max, blue_max, green_min, orange_green_max = tables
        r, g, b = cv2.split(np.ascontiguousarray(img[..., :3]))
        green = cv2.max(r, b) <= cv2.LUT(g, green_max)
        orange = (b <= cv2.LUT(r, blue_max)) & (g >= cv2.LUT(r, green_min)) & (g <= cv2.LUT(r, orange_green_max))
        return green, orange
    r, g, b = (img[..., k].astype(np.int16) for k in range(3))
    c = config
    green = (g >= c.min_level) & (g - np.maximum(r, b) >= c.green_dominance * g)
    lo, hi = c.orange_green_share
    orange = ((r >= c.min_level) & (b <= c.orange_blue_share * r)
              & (g >= lo * r) & (g <= hi * r))
    return green, orange


class ObstacleDetector:
    """Finds boxes and cones in image pairs of calibrated cameras (GroundMap per camera, same order)."""

    def __init__(self, ground_maps: Sequence[GroundMap], config: ObstacleConfig = ObstacleConfig()):
        self.ground_maps = list(ground_maps)
        self.config = config.check()

    def _blobs(self, mask, ground_map: GroundMap, kind: str, road_direction_rad: float = 0.0) -> List[Detection]:
        c = self.config
        if not mask.any():
            return []
        n, labels, stats, _ = cv2.connectedComponentsWithStats(mask.astype(np.uint8), connectivity=8)
        out = []
        for label in range(1, n):
            if stats[label, cv2.CC_STAT_AREA] < c.min_blob_px:
                continue
            # the blob's lowest row in each column, within its bounding box (it holds all of the blob)
            left, top, width, height = (int(stats[label, k]) for k in (cv2.CC_STAT_LEFT, cv2.CC_STAT_TOP,
                                                                       cv2.CC_STAT_WIDTH, cv2.CC_STAT_HEIGHT))
            blob = labels[top:top + height, left:left + width] == label
            in_column = blob.any(axis=0)
            u = left + np.flatnonzero(in_column)  # the columns holding it, left to right
            lowest = top + (height - 1) - blob[::-1].argmax(axis=0)[in_column]  # its last row in each
            xy = ground_map.xy_m[lowest, u]
            xy = xy[np.isfinite(xy[:, 0])]
            if len(xy) == 0:
                continue
            near_x = float(np.percentile(xy[:, 0], c.near_percentile))
            if near_x > c.max_range_m:
                continue
            # Columns beside the floor outline see the object's top edges at their lowest: they
            # land far behind the near edge and wide; keep the outline near the near edge.
            outline = xy[xy[:, 0] <= near_x + c.outline_depth_m]
            y_min, y_max = float(outline[:, 1].min()), float(outline[:, 1].max())
            far_x = self._far_x(xy, y_min, y_max, road_direction_rad)
            out.append(Detection(kind, near_x, y_min, y_max, int(np.count_nonzero(blob)), far_x))
        return out

    def _far_x(self, xy, y_min_m: float, y_max_m: float, road_direction_rad: float) -> float:
        """The far end [m] along the side facing the robot's axis of an outline (N, 2) [m] with
        lateral extent y_min_m .. y_max_m, that side running in road_direction_rad; NaN across the axis."""
        if y_min_m < 0.0 < y_max_m:
            return float("nan")
        c, s = math.cos(road_direction_rad), math.sin(road_direction_rad)
        along_m, across_m = xy[:, 0] * c + xy[:, 1] * s, -xy[:, 0] * s + xy[:, 1] * c  # the road's frame
        side_m = across_m.max() if y_max_m <= 0.0 else across_m.min()
        on_side = np.abs(across_m - side_m) <= self.config.side_band_m
        if not on_side.any():
            return float("nan")
        k = np.flatnonzero(on_side)[np.argmax(along_m[on_side])]
        return float(xy[k, 0])

    def _merge(self, detections: List[Detection]) -> List[Detection]:
        c = self.config
        gap = c.merge_gap_m
        merged: List[Detection] = []
        for d in sorted(detections, key=lambda d: d.y_min_m):
            dx_m = c.merge_box_dx_m if d.kind == BOX else c.merge_cone_dx_m
            for i, m in enumerate(merged):
                if (m.kind == d.kind and abs(m.near_x_m - d.near_x_m) <= dx_m
                        and d.y_min_m <= m.y_max_m + gap and m.y_min_m <= d.y_max_m + gap):
                    merged[i] = Detection(m.kind, min(m.near_x_m, d.near_x_m), min(m.y_min_m, d.y_min_m),
                                          max(m.y_max_m, d.y_max_m), m.pixels + d.pixels,
                                          _merged_far_x(m, d))
                    break
            else:
                merged.append(d)
        return sorted(merged, key=lambda d: d.near_x_m)

    def detect(self, images, road_direction_rad: float = 0.0) -> List[Detection]:
        """Boxes and cones in one image per ground map, nearest first.  road_direction_rad: the
        road's direction in base_footprint [rad] (minus the lane's heading error), along which
        the objects' sides run (far_x_m)."""
        found = []
        for image, gm in zip(images, self.ground_maps):
            green, orange = colour_masks(image, self.config)
            found += self._blobs(green, gm, BOX, road_direction_rad)
            found += self._blobs(orange, gm, CONE, road_direction_rad)
        return self._merge(found)


def _merged_far_x(a: Detection, b: Detection) -> float:
    """far_x_m of two blobs merged into one object: the far end of the side facing the axis (the
    blob reaching nearer the axis holds that side); NaN when the union lies across the axis."""
    y_min, y_max = min(a.y_min_m, b.y_min_m), max(a.y_max_m, b.y_max_m)
    if y_min < 0.0 < y_max:
        return float("nan")
    side = max((a, b), key=lambda d: d.y_max_m) if y_max <= 0.0 else min((a, b), key=lambda d: d.y_min_m)
    other = b if side is a else a
    # the other blob's far end counts where it reaches that side too (a face seen by each camera)
    if abs((other.y_max_m if y_max <= 0.0 else other.y_min_m) - (side.y_max_m if y_max <= 0.0 else side.y_min_m)) \
            <= 0.05 and math.isfinite(other.far_x_m):
        return max(side.far_x_m, other.far_x_m) if math.isfinite(side.far_x_m) else other.far_x_m
    return side.far_x_m


def lane_relative_extent(detection: Detection, lane_coeffs) -> Tuple[float, float]:
    """(y_min, y_max) of a detection measured from the lane's centre curve y = c0 + c1 x + c2 x^2
    (base_footprint, conde_tracking.lane_measurement) at the detection's near edge [m], + = left."""
    c0, c1, c2 = (float(v) for v in lane_coeffs)
    x = detection.near_x_m
    centre_y = c0 + c1 * x + c2 * x * x
    return detection.y_min_m - centre_y, detection.y_max_m - centre_y
