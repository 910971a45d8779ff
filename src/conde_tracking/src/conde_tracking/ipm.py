"""Inverse perspective mapping: camera pixels -> points on the ground plane z = 0.

Pure numpy + OpenCV, no ROS.  A camera is described by its CameraInfo intrinsics (K 3x3,
plumb_bob D = [k1 k2 p1 p2 k3]) and its pose in base_footprint as a 4x4 homogeneous matrix
T_base_optical (maps points in the REP 103 optical frame, z forward, x right, y down, to
base_footprint, x forward, y left, z up).  base_footprint lies on the ground, so the ground is
the plane z = 0 of that frame.

Assumptions: flat ground, rigid camera mount; the robot's roll/pitch on its suspension is
ignored (Conde has none).
"""
from dataclasses import dataclass

import cv2
import numpy as np

from conde_tracking.lens import optical_rays


def ground_points(pixels_px, camera_matrix, dist_coeffs, T_base_optical, max_range_m=np.inf, lens=None):
    """Ground points [m] in base_footprint for pixel coordinates (N, 2) (u right, v down).

    Each pixel is undistorted to a normalised ray, turned into base_footprint and intersected
    with z = 0.  Returns an (N, 2) array of (x, y); rays that do not hit the ground in front of
    the camera, or hit it farther than max_range_m from the camera, are NaN.  lens: None for a
    pinhole camera, else (image width [px], image height [px], a wide-angle lens type of lens.py)."""
    px = np.asarray(pixels_px, dtype=np.float64).reshape(-1, 1, 2)
    if len(px) == 0:
        return np.zeros((0, 2))
    width_px, height_px, lens_type = lens if lens is not None else (0, 0, "pinhole")
    rays_optical = optical_rays(px, width_px, height_px, camera_matrix, dist_coeffs, lens_type)
    T = np.asarray(T_base_optical, dtype=np.float64)
    rays = rays_optical @ T[:3, :3].T
    origin = T[:3, 3]
    with np.errstate(divide="ignore", invalid="ignore"):
        scale = -origin[2] / rays[:, 2]  # ray parameter at z = 0
    hit = origin[None, :2] + scale[:, None] * rays[:, :2]
    reach = scale * np.linalg.norm(rays, axis=1)
    bad = ~(rays[:, 2] < 0.0) | ~(scale > 0.0) | ~(reach <= max_range_m)
    hit[bad] = np.nan
    return hit


@dataclass
class GroundMap:
    """Per-pixel ground coordinates of one camera, computed once.

    xy_m[v, u] = (x, y) in base_footprint [m] of pixel (u, v)'s centre, NaN where the pixel sees
    no ground within max_range_m."""
    width_px: int
    height_px: int
    xy_m: np.ndarray  # (H, W, 2)

    @classmethod
    def from_camera(cls, width_px, height_px, camera_matrix, dist_coeffs, T_base_optical, max_range_m=3.0,
                    lens="pinhole"):
        """lens: "pinhole" or a wide-angle lens type of lens.py (CameraInfo cannot say which)."""
        u, v = np.meshgrid(np.arange(width_px, dtype=np.float64), np.arange(height_px, dtype=np.float64))
        pixels = np.column_stack([u.ravel(), v.ravel()])
        xy = ground_points(pixels, camera_matrix, dist_coeffs, T_base_optical, max_range_m,
                           None if lens == "pinhole" else (width_px, height_px, lens))
        return cls(int(width_px), int(height_px), xy.reshape(height_px, width_px, 2))

    def points(self, mask):
        """Ground points (N, 2) [m] of the pixels where the boolean (H, W) mask is set (NaN dropped)."""
        xy = self.xy_m[mask]
        return xy[np.isfinite(xy[:, 0])]


def birdseye_remap(width_px, height_px, camera_matrix, dist_coeffs, T_base_optical, x_range_m, y_range_m, cell_m=0.01):
    """cv2.remap tables for a metric bird's-eye grid (row 0 = farthest x, column 0 = leftmost y).

    For every cell centre the ground point is projected into the camera (with distortion);
    cells behind the camera or outside the image get -1 (remap leaves them at the border
    value).  Returns (map_u, map_v) float32 arrays of shape (n_x, n_y)."""
    h_px, w_px = height_px, width_px
    xs = np.arange(x_range_m[1] - cell_m / 2, x_range_m[0], -cell_m)
    ys = np.arange(y_range_m[1] - cell_m / 2, y_range_m[0], -cell_m)
    gx, gy = np.meshgrid(xs, ys, indexing="ij")
    pts = np.column_stack([gx.ravel(), gy.ravel(), np.zeros(gx.size)])
    T = np.linalg.inv(np.asarray(T_base_optical, np.float64))
    in_cam = pts @ T[:3, :3].T + T[:3, 3]
    rvec, _ = cv2.Rodrigues(T[:3, :3])
    uv, _ = cv2.projectPoints(pts.reshape(-1, 1, 3), rvec, T[:3, 3], np.asarray(camera_matrix, np.float64),
                              np.asarray(dist_coeffs, np.float64).ravel())
    uv = uv.reshape(-1, 2)
    outside = ((in_cam[:, 2] <= 0) | (uv[:, 0] < -0.5) | (uv[:, 0] > w_px - 0.5)
               | (uv[:, 1] < -0.5) | (uv[:, 1] > h_px - 0.5))
    uv[outside] = -1
    return (uv[:, 0].reshape(gx.shape).astype(np.float32), uv[:, 1].reshape(gx.shape).astype(np.float32))
