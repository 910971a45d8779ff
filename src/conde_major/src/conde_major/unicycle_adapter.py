"""Unicycle command (v, omega) -> Ackermann command (speed, steering angle), free of ROS.

A stack written for a differential-drive robot (conde_control's /cmd_vel) asks for a forward
speed v [m/s] and a yaw rate omega [rad/s]. A car drives its rear-axle centre on a circle of
curvature k = tan(delta) / L [1/m] (wheelbase L [m], steering angle delta [rad] of a virtual
wheel at the front-axle centre, + = left), so its yaw rate is v k. The same yaw rate at the same
speed needs

    delta = atan(omega L / v)

which holds backwards too (v < 0: the car turns the other way for the same steering angle).
What a car cannot do, and what this adapter does instead:
  - turn on the spot: below min_speed_mps |v| the curvature omega / v means nothing; the speed is
    passed on and the steering angle held (the wheels are not swung about while standing);
  - steer beyond its hinges: delta is limited to +-max_steering_rad;
  - steer at once: delta moves by at most max_steering_rate_radps [rad/s] times the time since
    the last command (0 = no limit).
The yaw rate actually commanded is then v tan(delta) / L; `yaw_rate_radps` says what it is.

Assumptions: no tyre slip (the kinematic bicycle model); v is the rear-axle centre's speed.
"""

import math
from dataclasses import dataclass

from conde_major.ackermann_targets import limit_rate


@dataclass(frozen=True)
class SteeringLimits:
    """The car's geometry and limits [m, rad, rad/s, m/s]."""
    wheelbase_m: float
    max_steering_rad: float            # largest |delta| of the virtual centre wheel, < pi/2
    max_steering_rate_radps: float = 0.0  # largest |d delta / dt|, 0 = none
    min_speed_mps: float = 0.01        # below this |v| the steering angle is held

    def __post_init__(self):
        if not (math.isfinite(self.wheelbase_m) and self.wheelbase_m > 0):
            raise ValueError('wheelbase_m must be a positive number, got %r' % self.wheelbase_m)
        if not 0 < self.max_steering_rad < math.pi / 2:
            raise ValueError('max_steering_rad must be in (0, pi/2), got %r' % self.max_steering_rad)
        if not (math.isfinite(self.max_steering_rate_radps) and self.max_steering_rate_radps >= 0):
            raise ValueError('max_steering_rate_radps must be a number >= 0, got %r' % self.max_steering_rate_radps)
        if not (math.isfinite(self.min_speed_mps) and self.min_speed_mps > 0):
            raise ValueError('min_speed_mps must be a positive number, got %r' % self.min_speed_mps)


@dataclass(frozen=True)
class AckermannCommand:
    speed_mps: float       # of the rear-axle centre, + = forward
    steering_rad: float    # of the virtual centre wheel, + = left
    yaw_rate_radps: float  # what this command turns the car at (no slip)


def steering_for(speed_mps, yaw_rate_radps, wheelbase_m):
    """The steering angle [rad] for `yaw_rate_radps` at `speed_mps` (speed != 0), unlimited."""
    return math.atan(yaw_rate_radps * wheelbase_m / speed_mps)


class UnicycleToAckermann:
    """Turns a stream of unicycle commands into Ackermann commands under SteeringLimits; keeps
    the last steering angle (for the rate limit and for standing still)."""

    def __init__(self, limits):
        self.limits = limits
        self._steering_rad = 0.0
        self._last_time_s = None

    def convert(self, speed_mps, yaw_rate_radps, time_s):
        """The command for (v [m/s], omega [rad/s]) received at `time_s` [s]; None (and nothing
        changes) when an input is not finite. Time going backwards (a reset) counts as none."""
        if not all(math.isfinite(x) for x in (speed_mps, yaw_rate_radps, time_s)):
            return None
        lim = self.limits
        dt_s = 0.0 if self._last_time_s is None else max(0.0, time_s - self._last_time_s)
        self._last_time_s = time_s
        if abs(speed_mps) >= lim.min_speed_mps:
            target = steering_for(speed_mps, yaw_rate_radps, lim.wheelbase_m)
            target = max(-lim.max_steering_rad, min(lim.max_steering_rad, target))
            # The wheels start straight; the first command has no time before it to turn them.
            self._steering_rad = limit_rate(self._steering_rad, target, lim.max_steering_rate_radps, dt_s)
        return AckermannCommand(speed_mps=speed_mps, steering_rad=self._steering_rad,
                                yaw_rate_radps=speed_mps * math.tan(self._steering_rad) / lim.wheelbase_m)
