"""Where the crosswalk ahead is, from the distance driven and the sightings of conde_tracking.
Pure Python, no ROS.

The robot starts standing at a crosswalk.  It reaches one when the near edge is within zone_m
ahead, and leaves it when it has driven length_m past the near edge (base_footprint beyond the
far edge).  Sightings are ignored from the moment the robot reaches a crosswalk until it has
driven rearm_m past the far edge (the stripes under and behind the robot are not a new
crosswalk)."""

import math
from typing import Optional


class CrosswalkTracker:
    def __init__(self, length_m: float, zone_m: float, rearm_m: float, start_to_near_edge_m: float = 0.0):
        self.length_m = length_m  # near edge to far edge along the road [m]
        self.zone_m = zone_m  # "at" the crosswalk within this distance of the near edge [m]
        self.rearm_m = rearm_m  # sightings ignored for this distance past the far edge [m]
        self.to_near_edge_m: Optional[float] = start_to_near_edge_m  # None: no crosswalk ahead known
        self.at_crosswalk = True  # reached and not yet left
        self.since_left_m: Optional[float] = None  # distance driven past the far edge of the last one

    def advance(self, step_m: float) -> None:
        """The robot drove step_m [m] along the road."""
        if self.to_near_edge_m is not None:
            self.to_near_edge_m -= step_m
        if self.since_left_m is not None:
            self.since_left_m += step_m

    def on_sighting(self, seen: bool, distance_m: float) -> None:
        """A lane measurement's crosswalk fields: seen, and the distance to its near edge [m]."""
        rearmed = self.since_left_m is None or self.since_left_m >= self.rearm_m
        if not self.at_crosswalk and rearmed and seen and math.isfinite(distance_m):
            self.to_near_edge_m = distance_m

    def ahead_within(self, range_m: float) -> bool:
        """A crosswalk ahead is known and its near edge is at most range_m [m] ahead (or behind)."""
        return self.to_near_edge_m is not None and self.to_near_edge_m <= range_m

    def reached(self, zone_m: Optional[float] = None) -> bool:
        """True once, when the robot arrives at the crosswalk ahead (within zone_m [m] of its near
        edge; None: the tracker's zone_m)."""
        zone_m = self.zone_m if zone_m is None else zone_m
        if self.to_near_edge_m is not None and not self.at_crosswalk and self.to_near_edge_m <= zone_m:
            self.at_crosswalk = True
            return True
        return False

    def left(self) -> bool:
        """True once, when the robot has driven off the crosswalk it is at (past its far edge)."""
        if self.at_crosswalk and self.to_near_edge_m is not None and self.to_near_edge_m <= -self.length_m:
            self.at_crosswalk = False
            self.since_left_m = -self.length_m - self.to_near_edge_m  # >= 0: how far past the far edge
            self.to_near_edge_m = None
            return True
        return False
