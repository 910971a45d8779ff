"""Clamping and rate limiting of a commanded value (speed [m/s], turn rate [rad/s], ...).

Pure Python, no ROS.  One rate limiter for every node that ramps a command: conde_control's
acceleration limits, the decision's dead-reckoned speed (which must ramp exactly as
conde_control does, or the distance it reckons is not what the robot drives) and teleop.
"""

import math


def clamp(value: float, low: float, high: float) -> float:
    """value limited to [low, high] (low <= high)."""
    return max(low, min(high, value))


def clip(value: float, limit: float) -> float:
    """value limited to [-limit, +limit] (limit >= 0)."""
    return clamp(value, -limit, limit)


def approach(current: float, target: float, max_step: float) -> float:
    """One step from current toward target, at most max_step (>= 0) in size."""
    return current + clip(target - current, max_step)


class RateLimiter:
    """A value that follows its target at no more than max_rate_per_s [unit/s].

    step(target, dt_s) moves the value one time step toward the target and returns it; reset()
    sets it without limit (e.g. to 0 when the robot is known to stand)."""

    def __init__(self, max_rate_per_s: float, value: float = 0.0):
        if not (math.isfinite(max_rate_per_s) and max_rate_per_s > 0.0):
            raise ValueError("max_rate_per_s must be finite and > 0, got %r" % (max_rate_per_s,))
        self.max_rate_per_s = max_rate_per_s
        self.value = value

    def step(self, target: float, dt_s: float) -> float:
        if not (math.isfinite(dt_s) and dt_s >= 0.0):
            raise ValueError("dt_s must be finite and >= 0, got %r" % (dt_s,))
        self.value = approach(self.value, target, self.max_rate_per_s * dt_s)
        return self.value

    def reset(self, value: float = 0.0) -> None:
        self.value = value
