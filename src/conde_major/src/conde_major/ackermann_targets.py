"""Ackermann steering for a car whose four wheels are all driven, free of ROS.

A command is a speed v [m/s] of the rear-axle centre and a steering angle delta [rad] of a
virtual wheel at the front-axle centre (ackermann_msgs' convention; + = left). With the wheelbase
L [m], the half distance d [m] between the steering hinges and the curvature k = tan(delta) / L
[1/m] (the rear-axle centre turns on a circle of radius R = 1 / k), each front wheel points at
the turning centre and each wheel rolls at the speed of its own circle:

    left hinge   atan(k L / (1 - k d))          = atan(L / (R - d))
    right hinge  atan(k L / (1 + k d))          = atan(L / (R + d))
    rear left    v (1 - k d) / r                = v (R - d) / (R r)
    rear right   v (1 + k d) / r                = v (R + d) / (R r)
    front left   v hypot(1 - k d, k L) / r      = v sqrt((R - d)^2 + L^2) / (|R| r)
    front right  v hypot(1 + k d, k L) / r      = v sqrt((R + d)^2 + L^2) / (|R| r)

with r [m] each wheel's radius; wheel speeds in rad/s. Written with k rather than R, the formulas
hold for driving straight (k = 0) too. Assumptions: the rear wheels are on one axle, the hinges on
another parallel to it, at the same lateral distance d from the centre line as the wheels; no
tyre slip.
"""

import math
from dataclasses import dataclass


@dataclass(frozen=True)
class CarGeometry:
    """What the targets depend on [m, rad]."""
    wheelbase_m: float
    half_track_m: float            # half the distance between the steering hinges
    left_front_radius_m: float
    right_front_radius_m: float
    left_rear_radius_m: float
    right_rear_radius_m: float
    max_steering_rad: float = math.pi / 2  # largest |delta| of the virtual centre wheel

    def __post_init__(self):
        for name in ('wheelbase_m', 'half_track_m', 'left_front_radius_m', 'right_front_radius_m',
                     'left_rear_radius_m', 'right_rear_radius_m'):
            value = getattr(self, name)
            if not (math.isfinite(value) and value > 0):
                raise ValueError('%s must be a positive number, got %r' % (name, value))
        if not 0 < self.max_steering_rad <= math.pi / 2:
            raise ValueError('max_steering_rad must be in (0, pi/2], got %r' % self.max_steering_rad)


@dataclass(frozen=True)
class WheelTargets:
    """Set points of the six joint controllers: hinge angles [rad], wheel speeds [rad/s]."""
    left_steering_rad: float
    right_steering_rad: float
    left_front_radps: float
    right_front_radps: float
    left_rear_radps: float
    right_rear_radps: float


def max_centre_steering_rad(wheelbase_m, half_track_m, hinge_limit_rad):
    """The largest steering angle of the virtual centre wheel for which the inner hinge stays
    within `hinge_limit_rad`: from tan(limit) = k L / (1 - k d)."""
    tan_limit = math.tan(hinge_limit_rad)
    return math.atan(wheelbase_m * tan_limit / (wheelbase_m + half_track_m * tan_limit))


def wheel_targets(geometry, speed_mps, steering_rad):
    """Hinge angles and wheel speeds for driving the rear-axle centre at `speed_mps` with the
    centre steering angle `steering_rad` (limited to +-geometry.max_steering_rad)."""
    g = geometry
    steering_rad = max(-g.max_steering_rad, min(g.max_steering_rad, steering_rad))
    k = math.tan(steering_rad) / g.wheelbase_m  # curvature of the rear-axle centre's path [1/m]
    kl = k * g.wheelbase_m
    left, right = 1.0 - k * g.half_track_m, 1.0 + k * g.half_track_m
    return WheelTargets(
        left_steering_rad=math.atan2(kl, left),
        right_steering_rad=math.atan2(kl, right),
        left_front_radps=speed_mps * math.hypot(left, kl) / g.left_front_radius_m,
        right_front_radps=speed_mps * math.hypot(right, kl) / g.right_front_radius_m,
        left_rear_radps=speed_mps * left / g.left_rear_radius_m,
        right_rear_radps=speed_mps * right / g.right_rear_radius_m,
    )


def limit_rate(current, target, max_rate_per_s, dt_s):
    """Moves `current` toward `target` by at most max_rate_per_s * dt_s (no limit when the rate
    is <= 0, as in ackermann_msgs)."""
    if max_rate_per_s <= 0:
        return target
    step = max_rate_per_s * max(0.0, dt_s)
    return max(current - step, min(current + step, target))


class AckermannFollower:
    """Follows the latest command: rate limits when the command asks for them (its
    steering_angle_velocity [rad/s] and acceleration [m/s^2] fields, 0 = none), and after
    `cmd_timeout_s` of simulated or wall time without a command (0 = never) the wheels are
    commanded to 0 at once while the hinges hold their angle."""

    def __init__(self, geometry, cmd_timeout_s):
        if not (math.isfinite(cmd_timeout_s) and cmd_timeout_s >= 0):
            raise ValueError('cmd_timeout_s must be a number >= 0, got %r' % cmd_timeout_s)
        self.geometry = geometry
        self.cmd_timeout_s = cmd_timeout_s
        self._target_speed_mps = 0.0
        self._target_steering_rad = 0.0
        self._steering_rate_radps = 0.0
        self._acceleration_mps2 = 0.0
        self._command_time_s = None   # no command yet: stand still, wheels straight
        self._speed_mps = 0.0         # after the rate limits
        self._steering_rad = 0.0
        self._last_update_s = None

    def set_command(self, speed_mps, steering_rad, steering_rate_radps, acceleration_mps2, time_s):
        """A new command received at `time_s`; False (and ignored) when a field is not finite."""
        values = (speed_mps, steering_rad, steering_rate_radps, acceleration_mps2)
        if not all(math.isfinite(v) for v in values):
            return False
        self._target_speed_mps = speed_mps
        self._target_steering_rad = max(-self.geometry.max_steering_rad,
                                        min(self.geometry.max_steering_rad, steering_rad))
        self._steering_rate_radps = abs(steering_rate_radps)
        self._acceleration_mps2 = abs(acceleration_mps2)
        self._command_time_s = time_s
        return True

    def timed_out(self, time_s):
        if self._command_time_s is None:
            return True
        return self.cmd_timeout_s > 0 and time_s - self._command_time_s > self.cmd_timeout_s

    def update(self, time_s):
        """The targets at `time_s`. Time that goes backwards (a simulation reset) counts as no
        time passing."""
        dt_s = 0.0 if self._last_update_s is None else max(0.0, time_s - self._last_update_s)
        self._last_update_s = time_s
        if self._command_time_s is not None and time_s < self._command_time_s:
            self._command_time_s = time_s  # the clock was reset: the command is as new as now
        if self.timed_out(time_s):
            self._speed_mps = 0.0  # brake at once; the hinges keep their angle
        else:
            self._speed_mps = limit_rate(self._speed_mps, self._target_speed_mps, self._acceleration_mps2, dt_s)
            self._steering_rad = limit_rate(self._steering_rad, self._target_steering_rad,
                                            self._steering_rate_radps, dt_s)
        return wheel_targets(self.geometry, self._speed_mps, self._steering_rad)
