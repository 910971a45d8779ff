"""Where along a route a vertical sign's face can be read by a camera on the robot.  Pure numpy, no ROS.

A sign is a flat face (centre x, y [m], yaw [rad]; the face points along Rz(yaw) * (0, -1, 0), as
conde_worlds.challenge_objects places it).  From a point of a route (the lane centre, the robot's
heading along it) the face is *in reach* when the robot is in front of it, between min_distance_m
and max_distance_m from it and at most max_off_normal_deg off its normal; it is *in view* when it
is in reach and its bearing from the heading is within half_fov_deg of camera_yaw_deg.  The
defaults are Conde's top camera (90 deg wide, looking ahead) and conde_traffic_sign's working range
(sightings up to 4 m; the recogniser's accuracy measured up to 50 deg off the normal; closer than
0.4 m the 1.0 m high face leaves the image at the top).  The bearings in reach say what camera yaw
would show a sign that the front camera does not.

A camera elsewhere on the robot is described by its offset from the route point (camera_x_m,
camera_y_m, robot frame: x ahead, y left) and, to check that the whole face fits the image's
height and to give its size in pixels, its height, pitch and focal length (camera_z_m, not None).
Distances, bearings and angles are then taken from the camera, not from the route point.

random_view draws robot poses from which a camera sees a sign's face within a ViewRange (the
accuracy campaign, traffic_sign_accuracy); camera_limits gives a camera's ViewLimits from its
intrinsics and its pose on the robot, so that view_along checks each pose.
"""

import math
from dataclasses import dataclass
from typing import Optional, Tuple

import numpy as np

from conde_common.angles import wrap_rad


@dataclass(frozen=True)
class ViewLimits:
    min_distance_m: float = 0.4  # closer, the face leaves the top camera's image [m]
    max_distance_m: float = 4.0  # farther sightings are not used (sign_tracker) [m]
    max_off_normal_deg: float = 50.0  # the recogniser's accuracy was measured up to this [deg]
    half_fov_deg: float = 45.0  # half the camera's horizontal field of view [deg]
    camera_yaw_deg: float = 0.0  # the camera's axis from the robot's heading, + = left [deg]
    camera_x_m: float = 0.0  # the camera's position from the route point, robot frame, x ahead [m]
    camera_y_m: float = 0.0  # ... y left [m]
    camera_z_m: Optional[float] = None  # its height above the ground; None: no check of the face's height [m]
    camera_pitch_deg: float = 0.0  # its axis above the horizontal, + = up [deg]
    half_vfov_deg: float = 36.87  # half the image's height as an angle (320x240, 90 deg wide) [deg]
    focal_px: float = 160.0  # focal length (320 px wide, 90 deg) [px]
    face_centre_z_m: float = 1.0  # height of the sign face's centre (conde_worlds.challenge_objects) [m]
    face_size_m: float = 0.305  # edge of the square face [m]


@dataclass(frozen=True)
class SignView:
    in_view_m: float  # length of route along which the face is in the camera's view [m]
    in_reach_m: float  # ... along which it is in reach, whatever the camera looks at [m]
    bearings_in_reach_deg: Optional[Tuple[float, float]]  # bearing range from the heading while in reach, + = left
    best_off_normal_deg: Optional[float]  # the least angle off the face's normal while in view [deg]
    nearest_m: float  # the route's least distance to the sign [m]
    distances_in_view_m: Optional[Tuple[float, float]] = None  # camera-to-face range while in view [m]
    off_normal_in_view_deg: Optional[Tuple[float, float]] = None  # angle off the face's normal while in view [deg]
    face_px_in_view: Optional[Tuple[float, float]] = None  # face height in the image while in view [px] (camera_z_m)


def face_normal(yaw_rad: float) -> np.ndarray:
    """Unit vector the sign's face points along (x, y)."""
    return np.array([math.sin(yaw_rad), -math.cos(yaw_rad)])


@dataclass(frozen=True)
class ViewAlong:
    """Per route point: the camera-to-face distance [m], angle off the face's normal [deg], bearing
    from the heading [deg, + = left], in reach, in view, the face's height in the image (None
    without camera_z_m) [px]."""
    distance_m: np.ndarray
    off_normal_deg: np.ndarray
    bearing_deg: np.ndarray
    reach: np.ndarray
    view: np.ndarray
    face_px: Optional[np.ndarray]


def view_along(xy, heading_rad, sign_xy, sign_yaw_rad: float, limits: ViewLimits = ViewLimits()) -> ViewAlong:
    """The sign's face seen from each route point: xy (N, 2) [m], heading_rad (N,)."""
    xy = np.asarray(xy, dtype=float)
    heading = np.asarray(heading_rad, dtype=float)
    c, s = np.cos(heading), np.sin(heading)
    camera_xy = xy + np.column_stack([c * limits.camera_x_m - s * limits.camera_y_m,
                                      s * limits.camera_x_m + c * limits.camera_y_m])
    to_sign = np.asarray(sign_xy, dtype=float) - camera_xy
    distance = np.hypot(to_sign[:, 0], to_sign[:, 1])
    safe = np.maximum(distance, 1e-9)
    off_normal = np.degrees(np.arccos(np.clip(-(to_sign @ face_normal(sign_yaw_rad)) / safe, -1.0, 1.0)))
    bearing = np.degrees(wrap_rad(np.arctan2(to_sign[:, 1], to_sign[:, 0]) - heading))
    reach = ((distance >= limits.min_distance_m) & (distance <= limits.max_distance_m)
             & (off_normal <= limits.max_off_normal_deg))
    off_axis = (bearing - limits.camera_yaw_deg + 180.0) % 360.0 - 180.0
    view = reach & (np.abs(off_axis) <= limits.half_fov_deg)
    face_px = None
    if limits.camera_z_m is not None:
        fits, face_px = _face_in_height(distance, off_axis, limits)
        view &= fits
    return ViewAlong(distance, off_normal, bearing, reach, view, face_px)


def sign_view(xy, heading_rad, sign_xy, sign_yaw_rad: float, limits: ViewLimits = ViewLimits(),
              closed: bool = True) -> SignView:
    """xy (N, 2) [m]: route points in driving order (closed: the last links to the first, as
    conde_worlds' lane_centres); heading_rad (N,): the heading along the route there."""
    xy = np.asarray(xy, dtype=float)
    heading = np.asarray(heading_rad, dtype=float)
    if xy.ndim != 2 or xy.shape[1] != 2 or len(xy) < 2 or heading.shape != (len(xy),):
        raise ValueError("expected xy of shape (N, 2), N >= 2, and one heading per point")
    step_m = np.hypot(*(np.roll(xy, -1, axis=0) - xy).T)  # each point stands for the step after it
    if not closed:
        step_m[-1] = step_m[-2]
    at = view_along(xy, heading, sign_xy, sign_yaw_rad, limits)
    distance, off_normal, bearing, reach, view, face_px = (
        at.distance_m, at.off_normal_deg, at.bearing_deg, at.reach, at.view, at.face_px)
    return SignView(
        in_view_m=float(step_m[view].sum()),
        in_reach_m=float(step_m[reach].sum()),
        bearings_in_reach_deg=_span(bearing[reach]),
        best_off_normal_deg=float(off_normal[view].min()) if view.any() else None,
        nearest_m=float(distance.min()),
        distances_in_view_m=_span(distance[view]),
        off_normal_in_view_deg=_span(off_normal[view]),
        face_px_in_view=_span(face_px[view]) if face_px is not None else None)


def _span(values) -> Optional[Tuple[float, float]]:
    return (float(values.min()), float(values.max())) if len(values) else None


def _face_in_height(distance_m, off_axis_deg, limits: ViewLimits):
    """(whether the face's top and bottom edges are inside the image's height, the face's height in
    the image [px]) of a pinhole camera at camera_z_m pitched camera_pitch_deg, for faces at
    horizontal distance_m and off_axis_deg from the camera's axis."""
    pitch = math.radians(limits.camera_pitch_deg)
    forward = distance_m * np.cos(np.radians(off_axis_deg))  # along the axis's horizontal direction
    rows = []
    for dz in (limits.face_size_m / 2.0, -limits.face_size_m / 2.0):
        up = limits.face_centre_z_m + dz - limits.camera_z_m
        depth = forward * math.cos(pitch) + up * math.sin(pitch)  # optical z
        down = forward * math.sin(pitch) - up * math.cos(pitch)  # optical y (image down)
        rows.append((depth, down / np.maximum(depth, 1e-9)))
    (top_depth, top), (bottom_depth, bottom) = rows
    half = math.tan(math.radians(limits.half_vfov_deg))
    fits = (top_depth > 0) & (bottom_depth > 0) & (top >= -half) & (bottom <= half)
    return fits, limits.focal_px * (bottom - top)


def condes_route(lanes: dict) -> Tuple[np.ndarray, np.ndarray]:
    """(xy (N, 2), heading (N,)) of the closed lap Conde drives (conde_decision): north loop
    counter-clockwise (straight on at the north fork, as route north_ccw), south loop counter-clockwise
    (the branch at the south fork, as route north_cw).  lanes: conde_worlds' Track.lane_centres(); the
    two routes are joined where they cross y = 0 southbound on the central straight (the same lane)."""
    def southbound_crossing(route):
        y = lanes[route]["xy"][:, 1]
        return int(np.flatnonzero((y[:-1] > 0.0) & (y[1:] <= 0.0))[0]) + 1

    north, south = lanes["north_ccw"], lanes["north_cw"]
    i, j = southbound_crossing("north_ccw"), southbound_crossing("north_cw")
    return (np.vstack([north["xy"][:i], south["xy"][j:]]),
            np.concatenate([north["heading"][:i], south["heading"][j:]]))


@dataclass(frozen=True)
class ViewRange:
    """Where random views of a face are taken from: between min_distance_m and max_distance_m from
    the face's centre, at most max_off_normal_deg off its normal, the camera's axis turned at most
    max_off_axis_deg from the face's centre (each uniform) [m, deg]."""
    min_distance_m: float
    max_distance_m: float
    max_off_normal_deg: float
    max_off_axis_deg: float


def camera_limits(view_range: ViewRange, camera_to_base, K) -> ViewLimits:
    """ViewLimits of a camera (camera_to_base 4x4: optical frame z forward, x right, y down -> robot
    frame; K 3x3) for the views of view_range: the camera's offset, height, yaw and pitch in the robot
    frame, its focal length and half the image height as an angle."""
    T, K = np.asarray(camera_to_base, dtype=float), np.asarray(K, dtype=float)
    axis = T[:3, 2]
    return ViewLimits(
        min_distance_m=view_range.min_distance_m, max_distance_m=view_range.max_distance_m,
        max_off_normal_deg=view_range.max_off_normal_deg, half_fov_deg=view_range.max_off_axis_deg,
        camera_yaw_deg=math.degrees(math.atan2(axis[1], axis[0])), camera_x_m=float(T[0, 3]),
        camera_y_m=float(T[1, 3]), camera_z_m=float(T[2, 3]),
        camera_pitch_deg=math.degrees(math.asin(max(-1.0, min(1.0, axis[2])))),
        half_vfov_deg=math.degrees(math.atan2(K[1, 2], K[1, 1])), focal_px=float(K[1, 1]))


def hidden(camera_xy, face_pose, other_faces, face_size_m: float = ViewLimits.face_size_m) -> bool:
    """Whether one of other_faces [(x, y, yaw)] stands between the camera at camera_xy and the face at
    face_pose (x, y, yaw), hiding any of it: seen from the camera, the two faces' horizontal extents
    (segments face_size_m wide along Rz(yaw) * (1, 0, 0)) overlap in bearing and the other's centre
    is nearer."""
    camera = np.asarray(camera_xy, dtype=float)

    def extent(pose):
        x, y, yaw = pose
        half = 0.5 * face_size_m * np.array([math.cos(yaw), math.sin(yaw)])
        ends = np.array([[x, y] + half, [x, y] - half]) - camera
        return np.arctan2(ends[:, 1], ends[:, 0]), math.hypot(x - camera[0], y - camera[1])

    (a, b), distance = extent(face_pose)
    centre = math.atan2(face_pose[1] - camera[1], face_pose[0] - camera[0])

    def from_centre(bearings):
        return sorted(wrap_rad(bearing - centre) for bearing in bearings)

    low, high = from_centre((a, b))
    for other in other_faces:
        ends, other_distance = extent(other)
        if other_distance >= distance:
            continue
        o_low, o_high = from_centre(ends)
        if o_low <= high and o_high >= low:
            return True
    return False


def random_view(sign_pose, rng, view_range: ViewRange, mount: Optional[ViewLimits] = None, other_faces=(),
                max_draws: int = 1000) -> Tuple[float, float, float]:
    """A robot pose (x, y, yaw) [m, rad] drawn with rng (numpy Generator) that shows the face at
    sign_pose (x, y, yaw) from within view_range.  mount (camera_limits): distances and angles are
    taken from that camera, and poses are drawn again until view_along finds the face in its view
    (the whole face within the image's height) and none of other_faces hides it (hidden);
    ValueError after max_draws.  Without a mount they are taken from the robot's origin, looking
    ahead, unchecked."""
    sx, sy, syaw = sign_pose
    normal = syaw - math.pi / 2  # the direction of face_normal(syaw)
    for _ in range(max_draws):
        off = normal + math.radians(rng.uniform(-view_range.max_off_normal_deg, view_range.max_off_normal_deg))
        distance = rng.uniform(view_range.min_distance_m, view_range.max_distance_m)
        cx, cy = sx + distance * math.cos(off), sy + distance * math.sin(off)
        axis = math.atan2(sy - cy, sx - cx) + math.radians(
            rng.uniform(-view_range.max_off_axis_deg, view_range.max_off_axis_deg))
        if mount is None:
            return cx, cy, axis
        yaw = axis - math.radians(mount.camera_yaw_deg)
        c, s = math.cos(yaw), math.sin(yaw)
        x, y = cx - (c * mount.camera_x_m - s * mount.camera_y_m), cy - (s * mount.camera_x_m + c * mount.camera_y_m)
        if view_along([[x, y]], [yaw], (sx, sy), syaw, mount).view[0] and not hidden((cx, cy), sign_pose, other_faces):
            return x, y, yaw
    raise ValueError("no view of the face at (%.2f, %.2f) within %s in %d draws" % (sx, sy, view_range, max_draws))
