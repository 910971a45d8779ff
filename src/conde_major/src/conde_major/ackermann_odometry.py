"""Wheel odometry of a car from its joint states, free of ROS.

The rear-axle centre travels the mean of the two rear wheels' rolled distances (their joint
angles times the wheel radius: the rear wheels are on one axle, so in a turn one rolls
(1 - k d) and the other (1 + k d) times the centre's distance, mean 1). The path's curvature k
[1/m] comes from the two steering hinges by Ackermann geometry (ackermann_targets.py):

    tan(left hinge)  = k L / (1 - k d)   ->   k = tan(left) / (L + d tan(left))
    tan(right hinge) = k L / (1 + k d)   ->   k = tan(right) / (L - d tan(right))

(L wheelbase, d half the hinges' distance [m]), the mean of the two. Each step is an arc of the
travelled length at the mean curvature of its two ends. The pose is that of the rear-axle centre,
starting at (0, 0, 0). Assumptions: no slip, flat ground.
"""

import math
from dataclasses import dataclass

from conde_common.angles import wrap_rad


@dataclass
class Pose2D:
    x_m: float = 0.0
    y_m: float = 0.0
    yaw_rad: float = 0.0


def curvature_from_hinges(left_rad, right_rad, wheelbase_m, half_track_m):
    """The rear-axle centre's path curvature [1/m] (+ = left) from the two hinge angles."""
    tl, tr = math.tan(left_rad), math.tan(right_rad)
    return (tl / (wheelbase_m + half_track_m * tl) + tr / (wheelbase_m - half_track_m * tr)) / 2


class AckermannOdometry:
    """Integrates joint states: `update` with the rear wheels' joint angles [rad] (+ = rolling
    forward) and the hinges' angles [rad] (+ = left); `pose`, `speed_mps`, `yaw_rate_radps`."""

    def __init__(self, wheelbase_m, half_track_m, rear_radius_m):
        for name, value in (('wheelbase_m', wheelbase_m), ('half_track_m', half_track_m),
                            ('rear_radius_m', rear_radius_m)):
            if not (math.isfinite(value) and value > 0):
                raise ValueError('%s must be a positive number, got %r' % (name, value))
        self.wheelbase_m, self.half_track_m, self.rear_radius_m = wheelbase_m, half_track_m, rear_radius_m
        self.pose = Pose2D()
        self.travelled_m = 0.0
        self.speed_mps = 0.0
        self.yaw_rate_radps = 0.0
        self._last = None  # (time, left wheel, right wheel, curvature)

    def reset(self):
        self.__init__(self.wheelbase_m, self.half_track_m, self.rear_radius_m)

    def update(self, time_s, left_rear_rad, right_rear_rad, left_hinge_rad, right_hinge_rad):
        """One joint-state sample at `time_s` [s]; False (and ignored) when a value is not finite.
        Time going backwards (a simulation reset) restarts the odometry at the origin."""
        values = (time_s, left_rear_rad, right_rear_rad, left_hinge_rad, right_hinge_rad)
        if not all(math.isfinite(v) for v in values):
            return False
        k = curvature_from_hinges(left_hinge_rad, right_hinge_rad, self.wheelbase_m, self.half_track_m)
        if self._last is not None and time_s < self._last[0]:
            self.reset()
        if self._last is not None:
            t0, l0, r0, k0 = self._last
            ds = self.rear_radius_m * ((left_rear_rad - l0) + (right_rear_rad - r0)) / 2
            dyaw = ds * (k0 + k) / 2
            # Exact for an arc: the chord points at the mean heading.
            chord = ds if abs(dyaw) < 1e-9 else 2 * math.sin(dyaw / 2) * ds / dyaw
            heading = self.pose.yaw_rad + dyaw / 2
            self.pose.x_m += chord * math.cos(heading)
            self.pose.y_m += chord * math.sin(heading)
            self.pose.yaw_rad = wrap_rad(self.pose.yaw_rad + dyaw)
            self.travelled_m += abs(ds)
            dt = time_s - t0
            if dt > 0:
                self.speed_mps, self.yaw_rate_radps = ds / dt, dyaw / dt
        self._last = (time_s, left_rear_rad, right_rear_rad, k)
        return True
