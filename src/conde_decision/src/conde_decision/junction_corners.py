"""The corners of the junctions' turns, placed along the road from the line ends the cameras see.
Pure Python, no ROS.

At a junction the line on the outside of the robot's lane toward the turn turns away around the
turn's corner: for a right turn the lane's own edge line (conde_tracking's right_line_end_m), for
a left turn the outer edge line of the lane on the left (far_left_line_end_m: the dashed centre
line's end is no mark, it ends anywhere within a dash period before the branch).  Both turn away
with the same radius (the fork's radius less the line spacing, 0.19 m on the competition track),
so each leaves its band corner_line_offset_m beyond the corner where the turn's arc begins.

A corner's place is the median of its sightings, not the latest one.  Near the corner the lane
follower bends toward the turning line (the tracker's fit follows its curve) and the line's end is
seen later and later: on D2 (track seed 14, ODE) the left merge's corner, placed within 0.06 m of
the drawn one from 0.58 m away, crept 0.34 m further while the robot closed in, the turn began
0.26 m past the corner and its arc ran onto the central road's far line.  The sightings from
further away, taken while the robot still heads along the road, are the majority when the corner
is reached.

`config` is any object with the fields min_line_end_m, corner_sight_m, corner_line_offset_m and
corner_lead_m (DecisionConfig)."""

import math
import statistics
from typing import Dict, List, Optional, Tuple

#: the lane measurement's field that marks each side's corners
LINE_END_FIELDS = {"right": "right_line_end_m", "left": "far_left_line_end_m"}
#: ... when conde_tracking measures the lane on the robot's left: that lane's left line is the far line
#: (the robot's own edge line is then not measured)
LINE_END_FIELDS_ONE_LANE_LEFT = {"right": None, "left": "left_line_end_m"}
SIDES = tuple(LINE_END_FIELDS)


def visible_sides(tracked_lanes_left: int) -> Tuple[str, ...]:
    """The sides whose corners a lane measurement against that lane can show (tracked_lanes_left: 0
    the own lane, 1 the lane on the left: the robot's own edge line, which marks a right turn's
    corner, is then not measured)."""
    if tracked_lanes_left == 0:
        return SIDES
    if tracked_lanes_left == 1:
        return tuple(side for side in SIDES if LINE_END_FIELDS_ONE_LANE_LEFT[side])
    return ()


class JunctionCorners:
    """Call update() with each lane measurement and the distance driven [m]: it returns the sides
    whose corner the robot has reached (within corner_lead_m)."""

    def __init__(self, config):
        self.config = config
        # the sightings of the corner in sight on each side: distance travelled [m] at it ([]: none)
        self.sightings_m: Dict[str, List[float]] = {side: [] for side in SIDES}

    @property
    def corner_at_m(self) -> Dict[str, Optional[float]]:
        """Distance travelled [m] at the corner in sight on each side, the median of its sightings
        (None: none in sight)."""
        return {side: statistics.median(seen) if seen else None for side, seen in self.sightings_m.items()}

    def update(self, lane, travelled_m: float, tracked_lanes_left: int = 0) -> Tuple[str, ...]:
        """The sides ("right", "left") at whose corner the robot is now, from this lane measurement
        and earlier ones (the corner is kept when the line's end leaves the view as the corner comes
        near; a sighting more than corner_sight_m from it is another corner); a corner long passed
        (corner_sight_m) is forgotten.  A measurement
        without a side's field shows no corner there.  tracked_lanes_left: 1 when the measurement is
        against the lane on the robot's left (see DecisionLogic), 0 when against its own."""
        c = self.config
        reached = []
        names = LINE_END_FIELDS_ONE_LANE_LEFT if tracked_lanes_left == 1 else LINE_END_FIELDS
        for side in SIDES:
            end_m = getattr(lane, names[side], float("nan")) if names[side] and tracked_lanes_left in (0, 1) \
                else float("nan")
            seen = self.sightings_m[side]
            at_m = statistics.median(seen) if seen else None
            if math.isfinite(end_m) and c.min_line_end_m <= end_m <= c.corner_sight_m:
                sighting_m = travelled_m + end_m - c.corner_line_offset_m
                if at_m is None or abs(sighting_m - at_m) > c.corner_sight_m:
                    self.sightings_m[side] = []
                self.sightings_m[side].append(sighting_m)
                at_m = statistics.median(self.sightings_m[side])
            elif at_m is not None and travelled_m > at_m + c.corner_sight_m:
                at_m = None
                self.sightings_m[side] = []
            if at_m is not None and travelled_m >= at_m - c.corner_lead_m:
                reached.append(side)
        return tuple(reached)
