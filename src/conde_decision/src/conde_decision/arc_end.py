"""Where a junction's arc, driven blind, may end on the lane the cameras see (the event
lane_aligned).  Pure Python, no ROS.

One lane fit is not trusted: in a right turn into the south loop (D1, track seed 1) a fit of one
frame, 44 deg into the 90 deg arc, showed "a lane" 0.1 rad off the robot's heading, a lane 41 deg
from the one the turn leads to, and the turn ended there; Major Alvega's tracker did the like 1 s
into such a turn.  So the turn ends only on a confirmed alignment (the lane_aligned_* fields of DecisionConfig):

* the robot has turned through at least lane_aligned_min_sweep of the arc's sweep
  (distance_m / radius_m),
* each of the last lane_aligned_frames confident measurements (confidence 1, both lines) shows a lane
  whose direction (the robot's heading less the heading error) lies within lane_aligned_direction_rad
  of the direction the arc leads to, and these frames agree with each other (one track: directions
  within lane_aligned_spread_rad, lateral offsets within lane_aligned_spread_m),
* the robot heads the way the lane follower would steer it at the offset it is at (within
  lane_aligned_rad): lane_aligned_approach_per_m x the offset toward the lane's centre, at
  most lane_aligned_max_approach_rad.
  Ending the arc aligned with the lane while 13 cm inside it left the follower to swing the robot
  22 deg back, its rear across the junction's corner line (D1, track seed 1, lap 2); heading toward
  the centre at the follower's own angle, the hand-over needs no swing.

The robot's heading comes from odometry where known, else from the arc driven (in_arc_m /
radius_m: the commanded arc).  Heading errors are + when the robot points left of the lane
(conde_msgs/LaneMeasurement), offsets + when the robot is left of the lane's centre.
"""

import math
from dataclasses import dataclass
from typing import List, Optional


@dataclass(frozen=True)
class LaneSighting:
    """One confident measurement in the arc: the lane's direction in the arc's frame and the offset."""

    lane_direction_rad: float  # relative to the robot's heading at the arc's start [rad]
    offset_m: float


class ArcEnd:
    """Call start() where an arc begins, then update() with each lane measurement in it; update()
    returns True where the turn may end (lane_aligned)."""

    def __init__(self, config):
        """config: a DecisionConfig (its lane_aligned_* fields)."""
        self.config = config
        self.start_yaw_rad: Optional[float] = None
        self.sightings: List[LaneSighting] = []

    def start(self, yaw_rad: Optional[float]) -> None:
        """An arc begins; yaw_rad: the odometry heading there (None: unknown)."""
        self.start_yaw_rad = yaw_rad
        self.sightings = []

    def turned_rad(self, yaw_rad: Optional[float], in_arc_m: float, radius_m: float, side: float) -> float:
        """The heading change since the arc's start toward its side (side +1 left, -1 right) [rad]."""
        if yaw_rad is not None and self.start_yaw_rad is not None:
            return side * (yaw_rad - self.start_yaw_rad)
        return in_arc_m / radius_m

    def approach_rad(self, offset_m: float) -> float:
        """The heading error the lane follower steers to at this offset (toward the centre) [rad]."""
        c = self.config
        limit_rad = c.lane_aligned_max_approach_rad
        return max(-limit_rad, min(limit_rad, -c.lane_aligned_approach_per_m * offset_m))

    def update(self, side: float, radius_m: float, distance_m: float, in_arc_m: float, yaw_rad: Optional[float],
               offset_m: float, heading_error_rad: float, confidence: float) -> bool:
        """side: +1 a left arc, -1 a right one; radius_m, distance_m: the arc's; in_arc_m: driven in it
        [m]; yaw_rad: odometry heading (None: unknown); the lane measurement's offset [m], heading
        error [rad] and confidence."""
        c = self.config
        sweep_rad = distance_m / radius_m
        turned_rad = self.turned_rad(yaw_rad, in_arc_m, radius_m, side)
        seen = (confidence >= 1.0 and math.isfinite(offset_m) and math.isfinite(heading_error_rad))
        lane_direction_rad = side * turned_rad - heading_error_rad if seen else math.nan
        if not (seen and abs(lane_direction_rad - side * sweep_rad) <= c.lane_aligned_direction_rad):
            self.sightings = []  # not the arc's new lane: the track begins again
            return False
        self.sightings = (self.sightings + [LaneSighting(lane_direction_rad, offset_m)])[-c.lane_aligned_frames:]
        if turned_rad < c.lane_aligned_min_sweep * sweep_rad or len(self.sightings) < c.lane_aligned_frames:
            return False
        directions = [s.lane_direction_rad for s in self.sightings]
        offsets = [s.offset_m for s in self.sightings]
        if (max(directions) - min(directions) > c.lane_aligned_spread_rad
                or max(offsets) - min(offsets) > c.lane_aligned_spread_m):
            return False
        # turned far enough: the heading error, coming down from the sweep, is at (or past) the approach heading
        return -side * (heading_error_rad - self.approach_rad(offset_m)) <= c.lane_aligned_rad
