"""A junction's arc tracked by odometry.  Pure Python, no ROS.

A junction's turn is an arc of known radius driven where the lane cannot be measured.  Driven as a
curvature alone (feed-forward), the robot's path is the arc only if the robot begins it heading
along the road and turns at once.  Major Alvega (D2, track seed 2, ODE) began the left merge after
the south loop pointing 0.15 rad right of the road (its lane follower had swerved on the junction's
lines) and still turning right; its steering took 0.4 s to turn to the arc's curvature, and the
arc ended 0.4 m beyond the lane's centre, over the central road's far line.

Tracked, the arc is a path fixed on the floor where the turn begins: it starts at the robot's
place, tangent to the road's direction seen before the turn (by odometry: the robot's heading less
the heading error of measurements with both lines) or, where that is unknown, to the robot's
heading; it bends toward the turn's side with the state's radius.  In each step the robot's place
is dead-reckoned from the distance driven along its odometry heading, and the lateral offset and
heading error against the arc go to the control law with the arc's curvature, which then steers
back onto the arc as it steers back onto a lane.

Frame: x along the road's direction at the start, y to its left, the arc's centre at (0, side *
radius).  Offsets are + when the robot is left of the path, heading errors + when it points left of
the path's direction (conde_msgs/ControlReference).
"""

import math
from typing import Optional, Tuple

from conde_common.angles import wrap_rad


class ArcTrack:
    """start() where a junction's arc begins; step() in each step of it (the offset and heading error
    against the arc); release() when it ends."""

    def __init__(self):
        self.active = False
        self.x_m = self.y_m = 0.0
        self.direction_rad = 0.0  # the path's direction at its start, in the odometry's frame [rad]
        self.radius_m = 1.0
        self.side = 1.0  # +1 a left arc, -1 a right one
        self.last_yaw_rad: Optional[float] = None
        self.begun_now = False  # start() came after this step's distance was driven (before the arc)

    def start(self, yaw_rad: Optional[float], road_direction_rad: Optional[float], radius_m: float,
              side: float) -> bool:
        """An arc of radius_m [m] toward side (+1 left, -1 right) begins at the robot's place; yaw_rad:
        its odometry heading (None: unknown, the arc is not tracked); road_direction_rad: the road's
        direction seen before the turn (None: the robot's heading).  True when it is tracked."""
        if not (radius_m > 0.0 and side in (1.0, -1.0)):
            raise ValueError("arc track: expected a radius > 0 and a side of +-1, got %r, %r" % (radius_m, side))
        self.active = yaw_rad is not None and math.isfinite(yaw_rad)
        if not self.active:
            return False
        direction_rad = road_direction_rad if road_direction_rad is not None else yaw_rad
        self.x_m = self.y_m = 0.0
        self.direction_rad = yaw_rad + wrap_rad(direction_rad - yaw_rad)  # on the heading's branch
        self.radius_m, self.side = radius_m, side
        self.last_yaw_rad = yaw_rad
        self.begun_now = True
        return True

    def step(self, yaw_rad: Optional[float], step_m: float) -> Optional[Tuple[float, float]]:
        """(lateral offset [m], heading error [rad]) against the arc after the robot drove step_m [m]
        (+ forward) to heading yaw_rad [rad]; None when the arc is not tracked.  The first step after
        start() moves nothing: its distance was driven before the arc began (the caller's step)."""
        if not self.active or yaw_rad is None or not math.isfinite(yaw_rad):
            return None
        if self.begun_now:
            self.begun_now, step_m = False, 0.0
        mean_rad = 0.5 * (self.last_yaw_rad + yaw_rad) - self.direction_rad  # the step's heading in the arc frame
        self.x_m += step_m * math.cos(mean_rad)
        self.y_m += step_m * math.sin(mean_rad)
        self.last_yaw_rad = yaw_rad
        return self.errors(yaw_rad)

    def errors(self, yaw_rad: float) -> Tuple[float, float]:
        """(lateral offset [m], heading error [rad]) of the robot at its dead-reckoned place with
        heading yaw_rad [rad] against the arc."""
        s, r = self.side, self.radius_m
        dx, dy = self.x_m, self.y_m - s * r  # from the centre
        distance_m = math.hypot(dx, dy)
        offset_m = s * (r - distance_m)
        path_rad = math.atan2(dy, dx) + s * 0.5 * math.pi  # the tangent at the nearest point of the circle
        return offset_m, wrap_rad(yaw_rad - self.direction_rad - path_rad)

    def release(self) -> None:
        self.active = False
