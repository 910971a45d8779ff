"""sign_visibility: a sign's face in a camera's view along a route, on a straight lane with known
geometry, and the V1 layout on the nominal track (the four inner signs never in the front camera's
view from the route Conde drives, north_ccw)."""

import math

import numpy as np
import pytest

from conde_traffic_sign.sign_visibility import (ViewLimits, ViewRange, camera_limits, face_normal, hidden,
                                                random_view, sign_view)

SPACING_M = 0.01


def straight_north(length_m=10.0):
    """A lane along x = 0 from y = 0 to y = length_m, driven north (heading +90 deg)."""
    y = np.arange(0.0, length_m, SPACING_M)
    return np.column_stack([np.zeros_like(y), y]), np.full(len(y), math.pi / 2)


def test_the_face_points_as_the_world_places_it():
    assert face_normal(0.0) == pytest.approx([0.0, -1.0])
    assert face_normal(math.pi / 2) == pytest.approx([1.0, 0.0])
    assert face_normal(math.pi) == pytest.approx([0.0, 1.0], abs=1e-12)


def test_a_sign_beside_the_lane_facing_the_traffic_is_in_view_ahead():
    xy, heading = straight_north()
    # 0.6 m right of the lane at y = 6, facing south (yaw 0: face to -y), towards the robots coming north.
    view = sign_view(xy, heading, (0.6, 6.0), 0.0, closed=False)
    # In reach from 4 m before it (distance <= 4 m) until off its normal by 50 deg (0.6 / tan 50 = 0.50 m
    # before it); in the 90 deg view until 45 deg to the right (0.6 m before it).
    first_y = 6.0 - math.sqrt(4.0 ** 2 - 0.6 ** 2)
    last_y = 6.0 - 0.6 / math.tan(math.radians(50.0))
    assert view.in_reach_m == pytest.approx(last_y - first_y, abs=0.03)
    assert view.in_view_m == pytest.approx(5.4 - first_y, abs=0.03)
    assert view.bearings_in_reach_deg[0] == pytest.approx(-50.0, abs=0.5)  # on the right
    assert view.bearings_in_reach_deg[1] == pytest.approx(-math.degrees(math.atan2(0.6, 6.0 - first_y)), abs=0.5)
    assert view.nearest_m == pytest.approx(0.6, abs=1e-6)


def test_a_sign_facing_away_from_the_traffic_is_in_reach_only_behind():
    xy, heading = straight_north()
    view = sign_view(xy, heading, (0.6, 6.0), math.pi, closed=False)  # face to +y: for robots coming south
    assert view.in_view_m == 0.0 and view.best_off_normal_deg is None
    low, high = view.bearings_in_reach_deg  # past it, driving away: behind on the right
    assert -180.0 <= low < high < -90.0 and view.in_reach_m > 3.0
    assert sign_view(xy[:500], heading[:500], (0.6, 6.0), math.pi, closed=False).bearings_in_reach_deg is None


def test_a_sign_facing_the_lane_sideways_needs_a_camera_turned_to_it():
    xy, heading = straight_north()
    # 1.5 m right of the lane, facing west (yaw -90 deg: face to -x), square to the lane.
    front = sign_view(xy, heading, (1.5, 6.0), -math.pi / 2, closed=False)
    right = sign_view(xy, heading, (1.5, 6.0), -math.pi / 2, ViewLimits(camera_yaw_deg=-60.0), closed=False)
    reach_m = 1.5 * math.tan(math.radians(50.0))  # either side of y = 6 while within 50 deg of its normal
    assert front.in_reach_m == pytest.approx(2 * reach_m, abs=0.03)
    assert front.bearings_in_reach_deg == pytest.approx((-140.0, -40.0), abs=0.5)
    assert front.in_view_m == pytest.approx(reach_m - 1.5, abs=0.03)  # only from -40 to -45 deg
    # The camera turned 60 deg right sees -15..-105 deg: from 50 deg before the normal to 15 deg past it.
    assert right.in_view_m == pytest.approx(reach_m + 1.5 / math.tan(math.radians(75.0)), abs=0.03)
    assert right.best_off_normal_deg == pytest.approx(0.0, abs=0.5)


def test_bad_route_arrays_are_refused():
    with pytest.raises(ValueError, match="shape"):
        sign_view(np.zeros((5, 3)), np.zeros(5), (0.0, 0.0), 0.0)
    with pytest.raises(ValueError, match="heading"):
        sign_view(np.zeros((5, 2)), np.zeros(4), (0.0, 0.0), 0.0)


def conde_and_other_way():
    """Per sign of the nominal V1 layout: its view from the way Conde drives its loop (the north loop
    as route north_ccw, the south loop as north_cw: the track's two routes each drive both loops, one
    way round each) and from the other way round that loop."""
    from conde_worlds.challenge_objects import sign_poses
    from conde_worlds.track_geometry import build_track

    lanes = build_track().lane_centres(0.02)
    out = {}
    for n, (x, y, yaw) in enumerate(sign_poses(), start=1):
        conde, other = ("north_ccw", "north_cw") if y > 0 else ("north_cw", "north_ccw")
        out[n] = tuple(sign_view(lanes[route]["xy"], lanes[route]["heading"], (x, y), yaw) for route in (conde, other))
    return out


def test_v1_inner_signs_are_out_of_the_front_cameras_view_on_condes_route():
    """Signs 8, 9, 11, 12 (inside the loops) are never in the front camera's view from Conde's route,
    the other eight are (as the driven V1 runs read them); from Conde's route those four are in reach
    only behind its side (more than 90 deg off its heading), from the other way round their loop on
    the right, 40-135 deg."""
    views = conde_and_other_way()
    assert sorted(n for n, (conde, _) in views.items() if conde.in_view_m > 0.0) == [1, 2, 3, 4, 5, 6, 7, 10]
    for n in (8, 9, 11, 12):
        conde, other = views[n]
        low, high = conde.bearings_in_reach_deg
        assert abs(low) > 90.0 and abs(high) > 90.0
        low, high = other.bearings_in_reach_deg
        assert -135.0 < low < high <= -40.0
    assert views[9][1].in_view_m == 0.0 and views[12][1].in_view_m == 0.0  # not the front camera either way


def test_a_camera_behind_the_route_point_measures_from_where_it_is():
    xy, heading = straight_north()
    here = sign_view(xy, heading, (0.6, 6.0), 0.0, closed=False)
    behind = sign_view(xy, heading, (0.6, 6.0), 0.0, ViewLimits(camera_x_m=-0.5), closed=False)
    assert behind.in_view_m == pytest.approx(here.in_view_m, abs=0.03)  # the same stretch, 0.5 m later
    assert behind.nearest_m == pytest.approx(0.6, abs=1e-6)
    first = sign_view(xy[:300], heading[:300], (0.6, 6.0), 0.0, closed=False)  # route y < 3: in reach from y 2.05
    first_behind = sign_view(xy[:300], heading[:300], (0.6, 6.0), 0.0, ViewLimits(camera_x_m=-0.5), closed=False)
    assert first.in_view_m - first_behind.in_view_m == pytest.approx(0.5, abs=0.03)


def test_the_face_must_fit_the_image_height_and_its_size_in_pixels_follows_the_pinhole():
    xy, heading = straight_north()
    level = ViewLimits(camera_z_m=1.0, max_distance_m=10.0, min_distance_m=0.0, max_off_normal_deg=90.0)
    view = sign_view(xy, heading, (0.0, 6.0), 0.0, level, closed=False)  # straight ahead, face-on
    low, high = view.face_px_in_view
    assert high == pytest.approx(160.0 * 0.305 / view.distances_in_view_m[0], rel=1e-3)
    assert low == pytest.approx(160.0 * 0.305 / view.distances_in_view_m[1], rel=1e-3)
    # the face's half height 0.1525 m leaves a 36.87 deg half height closer than 0.1525 / tan(36.87) = 0.203 m
    assert view.distances_in_view_m[0] == pytest.approx(0.1525 / 0.75, abs=0.011)
    low_camera = sign_view(xy, heading, (0.0, 6.0), 0.0, ViewLimits(camera_z_m=0.2, max_distance_m=10.0,
                                                                    min_distance_m=0.0), closed=False)
    assert low_camera.distances_in_view_m[0] == pytest.approx((1.1525 - 0.2) / 0.75, abs=0.011)
    pitched = sign_view(xy, heading, (0.0, 6.0), 0.0, ViewLimits(camera_z_m=0.2, camera_pitch_deg=36.87,
                                                                 max_distance_m=10.0, min_distance_m=0.0), closed=False)
    assert pitched.distances_in_view_m[0] < 0.5 * low_camera.distances_in_view_m[0]


def test_condes_lap_drives_both_loops_counter_clockwise():
    from conde_traffic_sign.sign_visibility import condes_route
    from conde_worlds.track_geometry import build_track

    xy, heading = condes_route(build_track().lane_centres(0.02))
    steps = np.hypot(*np.diff(np.vstack([xy, xy[:1]]), axis=0).T)
    assert steps.max() < 0.05  # one closed chain, no jump at either join
    for north in (True, False):
        part = xy[(xy[:, 1] > 3.0) if north else (xy[:, 1] < -3.0)]
        cx, cy = part.mean(axis=0)
        cross = np.cross(part[:-1] - (cx, cy), np.diff(part, axis=0))
        assert (cross > 0).mean() > 0.95  # counter-clockwise around the loop


TOP_CAMERA = ViewLimits(camera_x_m=-0.32, camera_z_m=0.78, camera_pitch_deg=16.0)  # conde.urdf.xacro
REAR_CAMERA = ViewLimits(camera_x_m=-0.66, camera_z_m=0.9, camera_yaw_deg=130.0)  # conde_traffic_sign README


@pytest.mark.parametrize("track_seed", [0, 3])
def test_v1_the_rear_left_camera_sees_the_four_inner_signs_face_on_from_condes_lap(track_seed):
    from conde_traffic_sign.sign_visibility import condes_route
    from conde_worlds.challenge_objects import sign_poses
    from conde_worlds.track_geometry import build_track
    from conde_worlds.track_variation import track_dimensions

    dims = track_dimensions(track_seed)  # 3: a track varied within the rules' tolerance
    xy, heading = condes_route(build_track(dims).lane_centres(0.02))
    for n, (x, y, yaw) in enumerate(sign_poses(dims), start=1):
        front = sign_view(xy, heading, (x, y), yaw, TOP_CAMERA)
        rear = sign_view(xy, heading, (x, y), yaw, REAR_CAMERA)
        assert (front.in_view_m > 0.0) == (n not in (8, 9, 11, 12)), n
        if n in (8, 9, 11, 12):
            assert rear.in_view_m > 3.0 and rear.best_off_normal_deg < 1.0, n
            assert rear.distances_in_view_m[1] < 3.9 and rear.face_px_in_view[0] > 14.0, n


def sign_camera_mount(yaw_deg=130.0, x_m=-0.66, z_m=0.9):
    """camera_to_base (optical frame: z forward, x right, y down) of a level camera turned yaw_deg left, and K
    of the 320x240, 90 deg camera."""
    yaw = math.radians(yaw_deg)
    forward = np.array([math.cos(yaw), math.sin(yaw), 0.0])
    right = np.array([math.sin(yaw), -math.cos(yaw), 0.0])
    T = np.eye(4)
    T[:3, 0], T[:3, 1], T[:3, 2], T[:3, 3] = right, [0.0, 0.0, -1.0], forward, [x_m, 0.0, z_m]
    return T, np.array([[160.0, 0.0, 160.0], [0.0, 160.0, 120.0], [0.0, 0.0, 1.0]])


def test_camera_limits_read_the_mount_from_the_camera_pose():
    T, K = sign_camera_mount()
    limits = camera_limits(ViewRange(1.4, 4.0, 50.0, 38.0), T, K)
    assert limits.camera_yaw_deg == pytest.approx(130.0)
    assert (limits.camera_x_m, limits.camera_y_m, limits.camera_z_m) == pytest.approx((-0.66, 0.0, 0.9))
    assert limits.camera_pitch_deg == pytest.approx(0.0, abs=1e-9)
    assert limits.half_vfov_deg == pytest.approx(36.87, abs=0.01)
    assert (limits.min_distance_m, limits.max_distance_m, limits.half_fov_deg) == (1.4, 4.0, 38.0)


def test_a_face_behind_another_is_hidden_one_beside_or_behind_it_is_not():
    face = (0.0, 4.0, 0.0)  # facing south, towards the camera at the origin
    assert hidden((0.0, 0.0), face, [(0.1, 2.0, 0.0)])          # in front, overlapping in bearing
    assert not hidden((0.0, 0.0), face, [(1.0, 2.0, 0.0)])      # in front, to the side
    assert not hidden((0.0, 0.0), face, [(0.0, 6.0, 0.0)])      # behind it
    assert not hidden((0.0, 0.0), face, [])
    # edge-on at 2 m, its 0.305 m width along the line of sight: still in front of the face
    assert hidden((0.0, 0.0), face, [(0.0, 2.0, math.pi / 2)])


def test_random_views_of_the_sign_camera_show_the_whole_face_inside_the_image():
    T, K = sign_camera_mount()
    view_range = ViewRange(1.4, 4.0, 50.0, 38.0)
    mount = camera_limits(view_range, T, K)
    sign = (-1.6, 5.0, 2.0)
    blocker = (-1.6, 3.5, 2.0)
    rng = np.random.default_rng(5)
    half = 0.305 / 2
    corners = [np.array([sign[0], sign[1], 1.0]) + np.array([math.cos(sign[2]) * a, math.sin(sign[2]) * a, b])
               for a in (-half, half) for b in (-half, half)]
    distances = []
    for _ in range(300):
        x, y, yaw = random_view(sign, rng, view_range, mount, [blocker])
        base_to_world = np.array([[math.cos(yaw), -math.sin(yaw), 0, x], [math.sin(yaw), math.cos(yaw), 0, y],
                                  [0, 0, 1, 0], [0, 0, 0, 1.0]])
        world_to_camera = np.linalg.inv(base_to_world @ T)
        for corner in corners:
            p = world_to_camera @ np.append(corner, 1.0)
            assert p[2] > 0
            u, v = (K @ (p[:3] / p[2]))[:2]
            assert 0 < u < 320 and 0 < v < 240
        camera_xy = (base_to_world @ T)[:2, 3]
        distances.append(math.hypot(sign[0] - camera_xy[0], sign[1] - camera_xy[1]))
        assert not hidden(camera_xy, sign, [blocker])
        to_camera = (camera_xy - sign[:2]) / distances[-1]
        assert math.degrees(math.acos(to_camera @ face_normal(sign[2]))) <= 50.0 + 1e-6
    assert min(distances) >= 1.4 and max(distances) <= 4.0
    assert max(distances) - min(distances) > 2.0  # spread over the range


def test_random_views_without_a_mount_are_taken_from_the_robot_looking_ahead():
    sign = (0.0, 4.0, 0.0)  # facing south
    rng = np.random.default_rng(1)
    for _ in range(200):
        x, y, yaw = random_view(sign, rng, ViewRange(0.8, 2.2, 50.0, 25.0))
        assert 0.8 <= math.hypot(x, y - 4.0) <= 2.2
        assert math.degrees(math.atan2(abs(x), 4.0 - y)) <= 50.0 + 1e-9
        off_axis = (math.atan2(4.0 - y, -x) - yaw + math.pi) % (2 * math.pi) - math.pi
        assert abs(math.degrees(off_axis)) <= 25.0 + 1e-9


def test_random_view_names_the_face_when_no_pose_fits():
    with pytest.raises(ValueError, match=r"\(0.00, 4.00\)"):
        random_view((0.0, 4.0, 0.0), np.random.default_rng(0), ViewRange(1.4, 4.0, 50.0, 38.0),
                    camera_limits(ViewRange(1.4, 4.0, 50.0, 38.0), *sign_camera_mount()), [(0.0, 3.0, 0.0)]
                    + [(0.4 * k, 3.0, 0.0) for k in range(-8, 9)], max_draws=50)
