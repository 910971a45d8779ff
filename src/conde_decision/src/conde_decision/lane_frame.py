"""Which lane conde_tracking measured, and the robot's offset from its own lane's centre.
Pure Python, no ROS.

conde_tracking measures the lateral offset against the lane whose lines it fitted and says which
one that is (LaneMeasurement.lane_index: 0 the right lane, the robot's own; 1 the lane on its left;
-1 not known, e.g. lines seen too briefly or at a junction), with the lanes' spacing it measured
(lane_spacing_m, from the line separation).  After a fork that opens right was crossed straight on
the tracker may have locked onto the lane on the left (ForkNavigator.tracker_may_be_on_the_other_lane):
there, and only there, the offset is taken in the own lane's frame:

* the tracked lane is the one whose centre is nearest: the offset modulo the line spacing of the
  config (line_spacing_m), as the robot keeps to its own lane outside an avoidance;
* where the index is known (0 / 1) and names that lane: lateral + index x the measured spacing (the
  config's when the tracker gave none), which is exact (the config's 0.8065 m is 2.5 cm more than
  the 0.782 m measured on the competition track);
* an index that names another lane (or -1) is not used: crossing a junction the tracker's index
  flips between 0, 1 and -1 from frame to frame while its offset stays against the same lane
  (recorded in D2, lap 2, at the north fork: -0.81 m with index 0, +0.14 m with index 1; taken as
  given the robot's offset jumped by a lane's width both ways and it turned round).

The avoidance is given the tracker's offset and index themselves: it places the lanes in its own
frame (avoidance.py), and the lane from here only to start from.

Outside that window the tracker's offset is used as it is (the lane it measures is the one to
follow).  Before these were joined, the modulo was applied whatever the index said: with the tracker
on the left lane the offset came out 2.5 cm off (0.8065 vs 0.782 m), and an avoidance given that
offset and lane_index 1 counted the lane twice."""

import math
from dataclasses import dataclass

#: LaneMeasurement.lane_index values
OWN_LANE, LEFT_LANE, UNKNOWN_LANE = 0, 1, -1


@dataclass(frozen=True)
class LaneFrame:
    """One lane measurement in the own lane's frame."""

    own_offset_m: float  # the robot from its own lane's centre (+ = left) [m]
    lanes_left: int  # how many lanes left of the own lane the tracked one lies (0: the own lane)
    spacing_m: float  # the spacing used for lanes_left [m] (0 when lanes_left is 0)
    source: str  # "tracker" (as measured), "index" (lane_index) or "modulo" (nearest lane)

    @property
    def shift_m(self) -> float:
        """The tracked lane's centre from the own lane's centre (+ = left) [m]."""
        return self.lanes_left * self.spacing_m


def known_index(lane_index) -> bool:
    return lane_index in (OWN_LANE, LEFT_LANE)


def lane_frame(lateral_offset_m: float, lane_index: int, lane_spacing_m: float, may_be_other_lane: bool,
               line_spacing_m: float) -> LaneFrame:
    """The measurement's offset [m] in the own lane's frame (see the module's docstring): the lane
    index where it agrees with the nearest lane, else the modulo.
    lane_index, lane_spacing_m [m]: conde_tracking's; may_be_other_lane: the tracker may measure
    the lane on the left; line_spacing_m [m]: the config's spacing, for the modulo."""
    if not may_be_other_lane or not math.isfinite(lateral_offset_m):
        return LaneFrame(lateral_offset_m, 0, 0.0, "tracker")
    lanes_left = -int(round(lateral_offset_m / line_spacing_m))
    if known_index(lane_index) and lane_index == lanes_left:
        spacing_m = lane_spacing_m if math.isfinite(lane_spacing_m) and lane_spacing_m > 0.0 else line_spacing_m
        return LaneFrame(lateral_offset_m + lane_index * spacing_m, lane_index, spacing_m, "index")
    return LaneFrame(nearest_lane_offset(lateral_offset_m, line_spacing_m), lanes_left, line_spacing_m, "modulo")


def nearest_lane_offset(offset_m: float, spacing_m: float) -> float:
    """A lateral offset [m] measured against any lane of parallel lanes spacing_m apart, as the
    offset from the nearest lane's centre."""
    return offset_m - spacing_m * round(offset_m / spacing_m)
