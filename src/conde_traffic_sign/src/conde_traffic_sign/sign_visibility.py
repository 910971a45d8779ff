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
"""

import math
from dataclasses import dataclass
from typing import Optional, Tuple

import numpy as np


@dataclass(frozen=True)
class ViewLimits:
    min_distance_m: float = 0.4  # closer, the face leaves the top camera's image [m]
    max_distance_m: float = 4.0  # farther sightings are not used (sign_tracker) [m]
    max_off_normal_deg: float = 50.0  # the recogniser's accuracy was measured up to this [deg]
    half_fov_deg: float = 45.0  # half the camera's horizontal field of view [deg]
    camera_yaw_deg: float = 0.0  # the camera's axis from the robot's heading, + = left [deg]


@dataclass(frozen=True)
class SignView:
    in_view_m: float  # length of route along which the face is in the camera's view [m]
    in_reach_m: float  # ... along which it is in reach, whatever the camera looks at [m]
    bearings_in_reach_deg: Optional[Tuple[float, float]]  # bearing range from the heading while in reach, + = left
    best_off_normal_deg: Optional[float]  # the least angle off the face's normal while in view [deg]
    nearest_m: float  # the route's least distance to the sign [m]


def face_normal(yaw_rad: float) -> np.ndarray:
    """Unit vector the sign's face points along (x, y)."""
    return np.array([math.sin(yaw_rad), -math.cos(yaw_rad)])


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
    to_sign = np.asarray(sign_xy, dtype=float) - xy
    distance = np.hypot(to_sign[:, 0], to_sign[:, 1])
    safe = np.maximum(distance, 1e-9)
    off_normal = np.degrees(np.arccos(np.clip(-(to_sign @ face_normal(sign_yaw_rad)) / safe, -1.0, 1.0)))
    bearing = np.degrees((np.arctan2(to_sign[:, 1], to_sign[:, 0]) - heading + math.pi) % (2 * math.pi) - math.pi)
    reach = ((distance >= limits.min_distance_m) & (distance <= limits.max_distance_m)
             & (off_normal <= limits.max_off_normal_deg))
    off_axis = np.abs((bearing - limits.camera_yaw_deg + 180.0) % 360.0 - 180.0)
    view = reach & (off_axis <= limits.half_fov_deg)
    return SignView(
        in_view_m=float(step_m[view].sum()),
        in_reach_m=float(step_m[reach].sum()),
        bearings_in_reach_deg=(float(bearing[reach].min()), float(bearing[reach].max())) if reach.any() else None,
        best_off_normal_deg=float(off_normal[view].min()) if view.any() else None,
        nearest_m=float(distance.min()))
