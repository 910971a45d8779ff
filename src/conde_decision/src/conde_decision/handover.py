"""The hand-over from a junction's blind arc to the lane follower.  Pure Python, no ROS.

A turn driven blind (turn_left / turn_right) ends on lane_aligned (arc_end.py) or after its stored
length, and rarely on the lane's centre.  Handed to the lane follower at once with an offset
reference of 0, the follower turns toward the centre at up to 0.62 rad, and the robot turns about
base_footprint, near its front: the turn swings the rear outwards.  At the end of a right turn
(D3 Bullet, track seed 3: 0.171 m right of the centre, pointing 0.238 rad left) the rear corner
touched the lane's outer line.

Instead, from the first confident lane measurement after the arc, the offset reference starts at the
offset measured there and eases to 0 linearly over handover_ease_m driven (as the avoidance's way
back eases its reference onto the lane), and the heading reference is that path's slope toward the
centre, atan(offset / handover_ease_m).  The follower then only has to keep the robot on a straight
line toward the centre, at about the heading the arc ended with, instead of turning sharply at once.
handover_ease_m = 0 turns the hand-over off (the reference is 0 at once, the behaviour before).

Offsets are + when the robot is left of the lane's centre, heading references + pointing left.
"""

import math
from typing import Optional, Tuple


class HandOver:
    """arm() in a blind arc; step() each step after it (it starts at the first confident lane)."""

    def __init__(self, ease_m: float):
        """ease_m: the distance driven over which the offset reference eases to 0 [m] (0: off)."""
        if not (math.isfinite(ease_m) and ease_m >= 0):
            raise ValueError("handover_ease_m: expected a finite number >= 0, got %r" % (ease_m,))
        self.ease_m = ease_m
        self.start_offset_m = 0.0
        self.start_travelled_m: Optional[float] = None
        self.armed = False  # a blind arc is being driven or has ended; waiting for a confident lane

    @property
    def active(self) -> bool:
        return self.start_travelled_m is not None

    def start(self, offset_m: float, travelled_m: float) -> None:
        """The lane follower takes over here, the robot offset_m [m] from the lane's centre."""
        if self.ease_m > 0 and math.isfinite(offset_m):
            self.start_offset_m = offset_m
            self.start_travelled_m = travelled_m

    def cancel(self) -> None:
        self.start_travelled_m = None

    def arm(self, in_arc: bool) -> None:
        """A step in a blind arc (in_arc) or in a lane change (not): any easing stops; after an arc
        the next confident lane starts one."""
        self.cancel()
        self.armed = in_arc

    def step(self, lane_ok: bool, offset_m: float, travelled_m: float) -> Tuple[float, float]:
        """(offset, heading) reference of a step outside arcs and lane changes; lane_ok: the lane
        (offset_m) is measured with confidence."""
        if self.armed and lane_ok:
            self.armed = False
            self.start(offset_m, travelled_m)
        if self.active and self._along_m(travelled_m) is None:
            self.cancel()  # eased all the way (or odometry went back): done until the next arc
        return self.reference(travelled_m)

    def _along_m(self, travelled_m: float) -> Optional[float]:
        """Distance driven since the start [m] while it is within [0, ease_m); otherwise None."""
        if self.start_travelled_m is None:
            return None
        along_m = travelled_m - self.start_travelled_m
        return along_m if 0.0 <= along_m < self.ease_m else None

    def reference(self, travelled_m: float) -> Tuple[float, float]:
        """(offset reference [m], heading reference [rad]) at travelled_m; (0, 0) when not easing.
        A query: it changes nothing (step() ends the easing)."""
        along_m = self._along_m(travelled_m)
        if along_m is None:
            return 0.0, 0.0
        offset_ref_m = self.start_offset_m * (1.0 - along_m / self.ease_m)
        return offset_ref_m, math.atan(-self.start_offset_m / self.ease_m)
