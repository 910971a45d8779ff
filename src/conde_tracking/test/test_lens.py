"""Pixel -> ray for pinhole and wide-angle cameras (conde_tracking/lens.py) and the ground map of
a wide-angle camera (ipm.GroundMap with lens=...): Major Alvega's tracking camera as its URDF
describes it (160 x 120, hfov 2.6 rad, stereographic, plumb_bob in image units about the
distortion centre), round trips through the forward model conde_sim renders with."""

import math

import cv2
import numpy as np
import pytest

from conde_tracking.ipm import GroundMap, ground_points
from conde_tracking.lens import LENSES, optical_rays, project_wide_angle

W, H, HFOV = 160, 120, 2.6
D_MAJOR = [-0.2673, 0.0629, 0.0012, -9.1477e-4, -0.0061]  # k1 k2 p1 p2 k3 (CameraInfo order)


def wide_k(lens="stereographic", width=W, height=H, center=(0.501996094, 0.4585875)):
    """CameraInfo K of conde_sim's wide-angle camera: f = 1 / radius(hfov / 2) (scale_to_hfov),
    fx = fy = f W / 2, the principal point at the distortion centre."""
    c1, c2, c3, fun = LENSES[lens]
    a = HFOV / 2 / c2 + c3
    edge = c1 * {"tan": math.tan, "sin": math.sin, "id": lambda v: v}[fun](a)
    f_px = width / 2 / edge
    return np.array([[f_px, 0, center[0] * width - 0.5], [0, f_px, center[1] * height - 0.5], [0, 0, 1]])


def major_tracking_pose():
    """T base_footprint <- camera_link_optical of Major Alvega (camera 0.295 m ahead of base_link,
    0.535 m up, pitched 0.76 rad down; base_footprint 0.16 m behind base_link)."""
    pitch = 0.76
    ry = np.array([[math.cos(pitch), 0, math.sin(pitch)], [0, 1, 0], [-math.sin(pitch), 0, math.cos(pitch)]])
    link_to_optical = np.array([[0, 0, 1], [-1, 0, 0], [0, -1, 0]], float)  # optical axes in the link frame
    T = np.eye(4)
    T[:3, :3] = ry @ link_to_optical
    T[:3, 3] = [0.295 + 0.16, 0, 0.535]
    return T


@pytest.mark.parametrize("lens", sorted(LENSES))
def test_pixel_ray_pixel_round_trip(lens):
    K = wide_k(lens)
    u, v = np.meshgrid(np.arange(5, W, 15, dtype=float), np.arange(5, H, 15, dtype=float))
    px = np.column_stack([u.ravel(), v.ravel()])
    rays = optical_rays(px, W, H, K, D_MAJOR, lens)
    ok = np.isfinite(rays[:, 0])
    assert ok.mean() > 0.75  # the orthographic lens shows no ray in the image corners
    back = project_wide_angle(rays[ok], W, H, K, D_MAJOR, lens)
    np.testing.assert_allclose(back, px[ok], atol=1e-3)
    np.testing.assert_allclose(np.linalg.norm(rays[ok], axis=1), 1.0, atol=1e-12)


def test_the_image_edge_is_at_half_the_field_of_view_without_distortion():
    K = wide_k()
    K[0, 2], K[1, 2] = (W - 1) / 2, (H - 1) / 2
    ray = optical_rays([[K[0, 2] + W / 2, K[1, 2]]], W, H, K, np.zeros(5), "stereographic")[0]
    assert math.atan2(ray[0], ray[2]) == pytest.approx(HFOV / 2, abs=1e-9)


def test_pinhole_rays_are_opencvs():
    K = np.array([[100.0, 0, 79.5], [0, 100.0, 59.5], [0, 0, 1]])
    D = [-0.25, 0.05, 0.005, 0.001, 0.0]
    px = np.array([[10.0, 20.0], [79.5, 59.5], [150.0, 100.0]])
    expected = cv2.undistortPoints(px.reshape(-1, 1, 2), K, np.array(D)).reshape(-1, 2)
    np.testing.assert_allclose(optical_rays(px, W, H, K, D)[:, :2], expected)
    assert (optical_rays(px, W, H, K, D)[:, 2] == 1).all()


def test_an_unknown_lens_is_refused_naming_it():
    with pytest.raises(ValueError, match="unknown lens type 'fisheye'"):
        optical_rays([[0, 0]], W, H, np.eye(3), np.zeros(5), "fisheye")


def test_ground_points_of_major_alvegas_camera_come_back_where_they_were():
    """Ground points 0.3-2 m ahead, +-0.6 m aside, projected through the lens into the image and
    mapped back through the wide-angle ground map: within 1 mm."""
    K, T = wide_k(), major_tracking_pose()
    gx, gy = np.meshgrid(np.linspace(0.3, 2.0, 8), np.linspace(-0.6, 0.6, 7))
    ground = np.column_stack([gx.ravel(), gy.ravel(), np.zeros(gx.size)])
    T_inv = np.linalg.inv(T)
    in_optical = ground @ T_inv[:3, :3].T + T_inv[:3, 3]
    px = project_wide_angle(in_optical, W, H, K, D_MAJOR, "stereographic")
    inside = (px[:, 0] >= 0) & (px[:, 0] <= W - 1) & (px[:, 1] >= 0) & (px[:, 1] <= H - 1)
    assert inside.sum() > 40
    back = ground_points(px[inside], K, D_MAJOR, T, lens=(W, H, "stereographic"))
    np.testing.assert_allclose(back, ground[inside, :2], atol=1e-3)
    # The pinhole reading of the same CameraInfo is far off: the lens matters.
    wrong = ground_points(px[inside], K, D_MAJOR, T)
    assert np.nanmax(np.abs(wrong - ground[inside, :2])) > 0.1


def test_ground_map_of_a_wide_angle_camera():
    K, T = wide_k(), major_tracking_pose()
    gm = GroundMap.from_camera(W, H, K, D_MAJOR, T, lens="stereographic")
    assert gm.xy_m.shape == (H, W, 2)
    # The bottom centre sees the ground just ahead of the camera, the top rows see no ground
    # within 3 m (the horizon is in the image).
    x, y = gm.xy_m[H - 1, W // 2]
    assert 0.0 < x < 0.6 and abs(y) < 0.05
    assert np.isnan(gm.xy_m[0, W // 2, 0])
