"""sign_visibility: a sign's face in a camera's view along a route, on a straight lane with known
geometry, and the V1 layout on the nominal track (the four inner signs never in the front camera's
view from the route Conde drives, north_ccw)."""

import math

import numpy as np
import pytest

from conde_traffic_sign.sign_visibility import ViewLimits, face_normal, sign_view

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
