"""Pixel -> viewing ray of a camera, pinhole or wide-angle.  Pure numpy + OpenCV, no ROS.

A pinhole camera's CameraInfo says everything: K and plumb_bob D, distortion on coordinates
normalised by the focal length (cv2.undistortPoints).

A wide-angle camera (Gazebo's <sensor type="wideanglecamera">, e.g. Major Alvega's two cameras)
maps a ray at angle theta from the optical axis to the radius r = c1 fun(theta / c2 + c3) on the
image plane of focal length 1 (LENSES: Gazebo's named lenses), and its plumb_bob distortion acts
on coordinates normalised by the image size (Gazebo's compositor; conde_sim renders it so). Its
CameraInfo gives K (fx = fy = the lens's focal length in pixels, the principal point = the
distortion centre) and D, but has no field for the lens, so the lens type comes from outside
(the URDF's <lens><type>, passed as a parameter).  Assumptions: no c3 offset other than the named
lenses' (custom lenses are not supported), square pixels.
"""
import cv2
import numpy as np

# Gazebo's named lenses: (c1, c2, c3, fun).
LENSES = {
    "gnomonical": (1.0, 1.0, 0.0, "tan"),
    "stereographic": (2.0, 2.0, 0.0, "tan"),
    "equidistant": (1.0, 1.0, 0.0, "id"),
    "equisolid_angle": (2.0, 2.0, 0.0, "sin"),
    "orthographic": (1.0, 1.0, 0.0, "sin"),
}
LENS_TYPES = ("pinhole",) + tuple(LENSES)


def optical_rays(pixels_px, width_px, height_px, camera_matrix, dist_coeffs, lens="pinhole"):
    """Unit-free rays (N, 3) in the camera's optical frame (z forward, x right, y down) for pixel
    coordinates (N, 2); rows of NaN where a wide-angle lens maps no ray to the pixel.  A pinhole
    ray has z = 1; a wide-angle ray has length 1."""
    if lens not in LENS_TYPES:
        raise ValueError("unknown lens type %r (expected one of: %s)" % (lens, ", ".join(LENS_TYPES)))
    px = np.asarray(pixels_px, dtype=np.float64).reshape(-1, 1, 2)
    if len(px) == 0:
        return np.zeros((0, 3))
    K = np.asarray(camera_matrix, np.float64).reshape(3, 3)
    D = np.asarray(dist_coeffs, np.float64).ravel()
    if lens == "pinhole":
        norm = cv2.undistortPoints(px, K, D).reshape(-1, 2)
        return np.column_stack([norm, np.ones(len(norm))])
    # Distortion in units of the image size about the principal point, then the lens's focal length.
    K_image = np.array([[width_px, 0.0, K[0, 2]], [0.0, height_px, K[1, 2]], [0.0, 0.0, 1.0]])
    # Far off the centre the distortion is strong: iterate to 1e-10 (cv2.undistortPoints stops at 5).
    criteria = (cv2.TERM_CRITERIA_COUNT | cv2.TERM_CRITERIA_EPS, 100, 1e-10)
    norm = cv2.undistortPointsIter(px, K_image, D, None, None, criteria).reshape(-1, 2)
    x, y = norm[:, 0] * width_px / K[0, 0], norm[:, 1] * height_px / K[1, 1]
    c1, c2, c3, fun = LENSES[lens]
    r = np.hypot(x, y)
    q = r / c1
    with np.errstate(invalid="ignore"):
        a = {"tan": np.arctan, "sin": np.arcsin, "id": lambda v: v}[fun](q)
    theta = c2 * (a - c3)
    s = np.sin(theta)
    with np.errstate(divide="ignore", invalid="ignore"):
        rays = np.column_stack([np.where(r > 0, s * x / r, 0.0), np.where(r > 0, s * y / r, 0.0), np.cos(theta)])
    rays[~np.isfinite(theta) | (theta < 0) | (theta > np.pi)] = np.nan
    return rays


def project_wide_angle(points_optical, width_px, height_px, camera_matrix, dist_coeffs, lens):
    """Pixel coordinates (N, 2) of points (N, 3) in the optical frame through a wide-angle lens
    (the forward model conde_sim renders with; NaN behind the lens's reach).  For tests and for
    drawing what a camera sees."""
    p = np.asarray(points_optical, np.float64).reshape(-1, 3)
    K = np.asarray(camera_matrix, np.float64).reshape(3, 3)
    k1, k2, p1, p2, k3 = (list(np.asarray(dist_coeffs, np.float64).ravel()) + [0.0] * 5)[:5]
    c1, c2, c3, fun = LENSES[lens]
    off = np.hypot(p[:, 0], p[:, 1])
    theta = np.arctan2(off, p[:, 2])
    a = theta / c2 + c3
    r = c1 * {"tan": np.tan, "sin": np.sin, "id": lambda v: v}[fun](a)
    with np.errstate(divide="ignore", invalid="ignore"):
        x = np.where(off > 0, r * p[:, 0] / off, 0.0) * K[0, 0] / width_px
        y = np.where(off > 0, r * p[:, 1] / off, 0.0) * K[1, 1] / height_px
    r2 = x * x + y * y
    radial = 1 + r2 * (k1 + r2 * (k2 + r2 * k3))
    xd = x * radial + 2 * p1 * x * y + p2 * (r2 + 2 * x * x)
    yd = y * radial + p1 * (r2 + 2 * y * y) + 2 * p2 * x * y
    return np.column_stack([width_px * xd + K[0, 2], height_px * yd + K[1, 2]])
