"""Holding the course straight across a junction by odometry.  Pure Python, no ROS.

Straight on at a fork that opens to the right (ForkNavigator.holds_course) the lane's edge line
turns away into the branch and the centre line has a gap: the lane follower would take the branch,
so the lane measurements are not used there.  Holding "whatever course the robot has" keeps the
heading it had when the hold began, and just before it the lane fit follows the lines that turn
into the branch: Major Alvega (D2, track seed 6, Bullet) began the hold pointing about 0.1 rad
right of the road and touched the far side's line 2.4 m later.

Instead the robot steers along the road's direction seen on the straight before the fork
(ForkNavigator.road_direction_rad, in the odometry's frame) and from its lateral offset seen there
(the median of the last few measurements with both lines that counted for that direction, before
the junction's lines lure the fit): while holding, the heading error is the odometry heading less
that direction and the offset is dead-reckoned from it (offset += sin(heading error) x the distance
driven).  Without odometry or without that direction the hold is the old one (the caller keeps its
references).

Offsets are + when the robot is left of the lane's centre, heading errors + when it points left
(conde_msgs/LaneMeasurement).
"""

import math
import statistics
from collections import deque
from typing import Deque, Optional, Tuple

from conde_common.angles import wrap_rad


class CourseHold:
    """measured() with each measurement that counts for the road's direction before a fork; step() in
    each step of the hold; release() when it is over."""

    def __init__(self, samples: int = 5):
        """samples: how many of the last measurements on the straight give the offset to start from."""
        if samples < 1:
            raise ValueError("course hold: samples must be >= 1, got %r" % (samples,))
        self.offsets_m: Deque[float] = deque(maxlen=samples)  # the last offsets seen on the straight [m]
        self.offset_m: Optional[float] = None  # dead-reckoned while holding [m] (None: not holding)

    def measured(self, offset_m: float) -> None:
        """A measurement (both lines) on the straight before a fork of the offset from the own lane's
        centre [m]."""
        if math.isfinite(offset_m):
            self.offsets_m.append(offset_m)

    def release(self) -> None:
        """The hold is over (the next one starts again from the offset measured then)."""
        self.offset_m = None

    def step(self, yaw_rad: Optional[float], road_direction_rad: Optional[float],
             step_m: float) -> Optional[Tuple[float, float]]:
        """(offset [m], heading error [rad]) of the robot against the road held along, after it drove
        step_m [m] more; None without the odometry's heading (yaw_rad) or the road's direction."""
        if yaw_rad is None or road_direction_rad is None:
            return None
        heading_error_rad = wrap_rad(yaw_rad - road_direction_rad)
        if self.offset_m is None:
            self.offset_m = statistics.median(self.offsets_m) if self.offsets_m else 0.0
        self.offset_m += step_m * math.sin(heading_error_rad)
        return self.offset_m, heading_error_rad
