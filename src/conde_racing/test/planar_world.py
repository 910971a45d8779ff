"""A small 2D world for the driver's tests: walls as line segments, a LiDAR that casts rays
against them, and a kinematic bicycle whose speed and steering follow their commands with a
first-order lag (standing in for the drive plugin's PIDs). Units: m, rad, s."""

import math

import numpy as np

from conde_racing import racetrack as rt


def cast(segments, origin_xy, yaw_rad, angles_rad, max_range_m=10.0):
    """Ranges from origin along yaw + angles to the nearest segment (rows x1 y1 x2 y2); +inf where
    nothing lies within max_range_m, as the simulator's LiDAR reports."""
    ox, oy = origin_xy
    s = np.asarray(segments, dtype=float)
    # only segments that may lie within range (segments are short compared with the range)
    near = np.minimum(np.hypot(s[:, 0] - ox, s[:, 1] - oy), np.hypot(s[:, 2] - ox, s[:, 3] - oy)) <= max_range_m + 0.5
    s = s[near]
    a = yaw_rad + np.asarray(angles_rad)
    dx, dy = np.cos(a)[:, None], np.sin(a)[:, None]
    ex, ey = s[:, 2] - s[:, 0], s[:, 3] - s[:, 1]
    wx, wy = s[:, 0] - ox, s[:, 1] - oy
    # ray o + t d meets segment a + u e where t = (w x e) / (d x e), u = (w x d) / (d x e)
    denom = dx * ey - dy * ex
    with np.errstate(divide="ignore", invalid="ignore"):
        t = (wx * ey - wy * ex) / denom
        u = (wx * dy - wy * dx) / denom
    hit = (t > 0) & (u >= 0) & (u <= 1) & np.isfinite(t)
    t = np.where(hit, t, np.inf).min(axis=1)
    return np.where(t <= max_range_m, t, np.inf)


def box_segments(cx, cy, length, width, yaw=0.0):
    """The four edges of a rectangle."""
    c, s = math.cos(yaw), math.sin(yaw)
    corners = [(cx + c * x - s * y, cy + s * x + c * y) for x, y in
               ((length / 2, width / 2), (-length / 2, width / 2), (-length / 2, -width / 2), (length / 2, -width / 2))]
    return [corners[i] + corners[(i + 1) % 4] for i in range(4)]


def racetrack_segments(line=None, spacing_m=0.05):
    """The racetrack's wall faces (HALF_WIDTH_M each side of the centre line) as segments."""
    line = line or rt.CentreLine()
    segments = []
    for lateral in (-rt.HALF_WIDTH_M, rt.HALF_WIDTH_M):
        pts = [line.point_at(s, lateral) for s in line.sample(spacing_m)[:, 0]]
        segments += [pts[i] + pts[(i + 1) % len(pts)] for i in range(len(pts))]
    return np.array(segments)


class Bicycle:
    """Kinematic bicycle about the rear-axle centre (base_footprint)."""

    def __init__(self, x, y, yaw, wheelbase_m=0.33, speed_lag_s=0.15, steering_lag_s=0.05):
        self.x, self.y, self.yaw = x, y, yaw
        self.speed, self.steering = 0.0, 0.0
        self.wheelbase_m, self.speed_lag_s, self.steering_lag_s = wheelbase_m, speed_lag_s, steering_lag_s

    def step(self, speed_cmd, steering_cmd, dt):
        self.speed += (speed_cmd - self.speed) * min(1.0, dt / self.speed_lag_s)
        self.steering += (steering_cmd - self.steering) * min(1.0, dt / self.steering_lag_s)
        self.x += self.speed * math.cos(self.yaw) * dt
        self.y += self.speed * math.sin(self.yaw) * dt
        self.yaw += self.speed * math.tan(self.steering) / self.wheelbase_m * dt

    def corners(self, rear_m=0.11, front_m=0.44, half_width_m=0.155):
        c, s = math.cos(self.yaw), math.sin(self.yaw)
        return [(self.x + c * x - s * y, self.y + s * x + c * y) for x in (-rear_m, front_m)
                for y in (-half_width_m, half_width_m)]
