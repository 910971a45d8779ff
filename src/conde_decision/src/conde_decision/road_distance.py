"""How far the robot has driven along the road [m] and its unwrapped heading [rad]; the road's
direction by odometry.  Pure Python.

The distance is the odometry's path length once odometry gives one, else dead-reckoned from the
commanded speed (which a robot that lags behind its commands, e.g. on a busy machine, does not
drive)."""

import math
from typing import Optional


def road_direction_rad(yaw_rad: Optional[float], heading_error_rad: float) -> Optional[float]:
    """The road's direction in the odometry's frame [rad]: the robot's heading yaw_rad less the
    heading error measured against the lane (+ = robot left of the road's direction); None when
    either is unknown (no odometry, a lane measurement without a heading).  The one rule that the
    fork navigator's loop sweeps, the avoidance and the lane recovery take the direction by."""
    if yaw_rad is None or not math.isfinite(yaw_rad) or not math.isfinite(heading_error_rad):
        return None
    return yaw_rad - heading_error_rad


class RoadDistance:
    def __init__(self):
        self.travelled_m = 0.0  # distance along the road since the start [m]
        self.yaw_rad: Optional[float] = None  # unwrapped heading from odometry [rad]
        self.odom_travelled_m: Optional[float] = None  # path length by odometry, latest [m]
        self.odom_used_m = 0.0  # ... as far as advance() has counted it [m]

    def on_odometry(self, yaw_rad: float, travelled_m: Optional[float] = None) -> None:
        """Heading [rad] (any branch of the angle) and, if known, the odometry's path length [m]."""
        if not math.isfinite(yaw_rad):
            return
        if travelled_m is not None and math.isfinite(travelled_m):
            if self.odom_travelled_m is None:
                self.odom_used_m = travelled_m
            self.odom_travelled_m = travelled_m
        if self.yaw_rad is None:
            self.yaw_rad = yaw_rad
        else:
            self.yaw_rad += math.remainder(yaw_rad - self.yaw_rad, 2.0 * math.pi)

    def advance(self, dead_reckoned_m: float) -> float:
        """One step: the distance driven since the last step [m] by odometry if known, else
        dead_reckoned_m; added to travelled_m and returned."""
        if self.odom_travelled_m is not None:
            step_m = max(0.0, self.odom_travelled_m - self.odom_used_m)
            self.odom_used_m = self.odom_travelled_m
        else:
            step_m = dead_reckoned_m
        self.travelled_m += step_m
        return step_m
