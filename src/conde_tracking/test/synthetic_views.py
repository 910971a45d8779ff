"""Ground-camera views of a straight lane drawn to chosen measures, for tests: the ground truth is
known by construction.  Each pixel is the mean of 3 x 3 samples of the ground (anti-aliased, as
the simulator's renderer), seen through the real cameras' intrinsics and poses of a rendered
test file."""
import math
from dataclasses import dataclass

import numpy as np

from conde_tracking.ipm import GroundMap

SUPERSAMPLE = 3


@dataclass
class StraightLane:
    lane_width_m: float = 0.746  # between the lines' inner edges [m]
    right_width_m: float = 0.085  # solid edge line [m]
    left_width_m: float = 0.036  # dashed centre line [m]
    dash_m: float = 0.20
    gap_m: float = 0.148
    white: int = 255
    black: int = 0

    def paint(self, along_m, left_m):
        """Grey level of ground points given along the lane and to the left of its centre [m]."""
        half = self.lane_width_m / 2
        right = (left_m <= -half) & (left_m >= -half - self.right_width_m)
        dashed = np.mod(along_m, self.dash_m + self.gap_m) < self.dash_m
        left = (left_m >= half) & (left_m <= half + self.left_width_m) & dashed
        return np.where(right | left, self.white, self.black)


def supersampled_map(width_px, height_px, K, D, T_base_optical):
    """GroundMap of the same camera at SUPERSAMPLE times the resolution (pixel centres kept)."""
    n = SUPERSAMPLE
    K_fine = np.array(K, float).copy()
    K_fine[0, 0] *= n
    K_fine[1, 1] *= n
    K_fine[0, 2] = n * (K[0, 2] + 0.5) - 0.5
    K_fine[1, 2] = n * (K[1, 2] + 0.5) - 0.5
    return GroundMap.from_camera(width_px * n, height_px * n, K_fine, D, T_base_optical)


def render(fine_map, lane, lateral_offset_m, heading_error_rad, light=1.0):
    """rgb8 image (H, W, 3) of the lane seen by a robot lateral_offset_m left of the lane centre and
    pointing heading_error_rad left of it, under a light level (0..1); the sky is light blue."""
    xy = fine_map.xy_m
    c, s = math.cos(heading_error_rad), math.sin(heading_error_rad)
    along = xy[..., 0] * c - xy[..., 1] * s
    left = xy[..., 0] * s + xy[..., 1] * c + lateral_offset_m
    grey = np.where(np.isfinite(along), lane.paint(np.nan_to_num(along), np.nan_to_num(left)) * light, 200.0)
    n = SUPERSAMPLE
    h, w = grey.shape[0] // n, grey.shape[1] // n
    grey = grey.reshape(h, n, w, n).mean(axis=(1, 3))
    return np.repeat(np.clip(np.round(grey), 0, 255).astype(np.uint8)[..., None], 3, axis=2)


@dataclass
class TwoLaneRoad(StraightLane):
    """Both lanes of a straight road: StraightLane's (the right lane, its centre at left_m = 0), its
    dashed centre line, and the left lane beyond it, as wide, with a solid edge line as the right one."""

    @property
    def lane_spacing_m(self):
        """The left lane's centre from the right lane's [m]."""
        return self.lane_width_m + self.left_width_m

    def paint(self, along_m, left_m):
        left_edge_m = self.lane_width_m / 2 + self.lane_spacing_m  # inner edge of the left lane's edge line
        far = (left_m >= left_edge_m) & (left_m <= left_edge_m + self.right_width_m)
        return np.where(far, self.white, super().paint(along_m, left_m))
