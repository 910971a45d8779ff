"""IPM against OpenCV's forward projection: ground points projected with cv2.projectPoints (same
K, D and camera pose) map back to themselves."""
import os

import cv2
import numpy as np
import pytest

from conde_tracking.ipm import GroundMap, birdseye_remap, ground_points

DATA = os.path.join(os.path.dirname(os.path.abspath(__file__)), "data")


def cameras():
    d = np.load(os.path.join(DATA, "centred.npz"))
    return [(d[f"{k}_K"], d[f"{k}_D"], d[f"{k}_T_base_optical"]) for k in ("left", "right")]


def project(points_xy, K, D, T_base_optical):
    T = np.linalg.inv(T_base_optical)
    pts = np.column_stack([points_xy, np.zeros(len(points_xy))])
    rvec, _ = cv2.Rodrigues(T[:3, :3])
    uv, _ = cv2.projectPoints(pts.reshape(-1, 1, 3), rvec, T[:3, 3], K, D)
    return uv.reshape(-1, 2)


@pytest.mark.parametrize("camera", [0, 1], ids=["left", "right"])
def test_projected_ground_points_map_back_within_1mm(camera):
    K, D, T = cameras()[camera]
    gx, gy = np.meshgrid(np.linspace(0.2, 1.5, 14), np.linspace(-0.8, 0.8, 17))
    ground = np.column_stack([gx.ravel(), gy.ravel()])
    uv = project(ground, K, D, T)
    inside = (uv[:, 0] > 0) & (uv[:, 0] < 159) & (uv[:, 1] > 0) & (uv[:, 1] < 119)
    assert inside.sum() > 50, "the test grid must lie in the camera's view"
    back = ground_points(uv[inside], K, D, T)
    err = np.hypot(*(back - ground[inside]).T)
    assert err.max() < 0.001, f"max error {err.max() * 1000:.3f} mm"


def test_ground_map_matches_ground_points_and_marks_the_sky():
    K, D, T = cameras()[0]
    gm = GroundMap.from_camera(160, 120, K, D, T, max_range_m=3.0)
    assert gm.xy_m.shape == (120, 160, 2)
    np.testing.assert_allclose(gm.xy_m[100, 40], ground_points([[40, 100]], K, D, T)[0], atol=1e-12)
    # the top corners of the images show the sky (rendered light blue in the test images)
    assert np.isnan(gm.xy_m[0, 0]).all() and np.isfinite(gm.xy_m[119, 80]).all()
    # a pixel's ground point projects back to that pixel
    uv = project(gm.xy_m[100, 40][None, :], K, D, T)[0]
    np.testing.assert_allclose(uv, [40, 100], atol=1e-3)


def test_rays_above_the_horizon_do_not_hit_the_ground():
    K, D, T = cameras()[1]
    # a camera looking straight up from 0.5 m sees no ground anywhere
    up = np.eye(4)  # optical z along base z (up)
    up[2, 3] = 0.5
    assert np.isnan(ground_points([[80, 60], [0, 0]], K, D, up)).all()


def test_birdseye_remap_puts_a_ground_point_on_its_cell():
    K, D, T = cameras()[0]
    map_u, map_v = birdseye_remap(160, 120, K, D, T, (0.0, 2.0), (-1.0, 1.0), cell_m=0.01)
    assert map_u.shape == (200, 200)
    # cell of ground point (1.005, 0.505): row (2.0 - 1.005) / 0.01 - 0.5, column (1.0 - 0.505) / 0.01 - 0.5
    u, v = map_u[99, 49], map_v[99, 49]
    np.testing.assert_allclose(ground_points([[u, v]], K, D, T)[0], [1.005, 0.505], atol=1e-4)
