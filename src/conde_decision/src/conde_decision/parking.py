"""Parking: which place the robot parks in, and the speeds of the parking manoeuvres.  Pure Python.

The manoeuvres themselves are states of config/conde_states.yaml (the park_* and bay_* blocks):
blind arcs and straights driven forward (speed ``creep``) or backward (speed ``reverse``) at
park_speed_mps for known distances, measured by odometry from where the lane was left.

The place: with the parameter parking_place set to a place, go_to_parking leaves on the event of
that place (parking_bay_north, parking_bay_south at once; parking_parallel once the robot has
driven parking_search_m in it), which fires in every step while the current state listens to it.
With parking_place "auto" (the default) the place is what the cameras show (BayFinder):
parking_bays_seen when a bay of the bay-parking area is known, parking_parallel when no line of
it was seen in the first parking_search_m (the parallel bay lies beyond the crosswalk, where the
P challenges start); then bay_entry_near fires where the straight into the first free bay seen
must begin, anchored on that bay's lines (bay_entry_lead_m before its centre), not on the start.
"""

from typing import List, Optional, Tuple

#: parking_place "auto": the place is the parking area the cameras show (no place event).
AUTO = "auto"
#: The places, each with the event that sends go_to_parking toward it; "auto": the place seen.
PARKING_PLACES = ("auto", "parallel", "bay_north", "bay_south")
#: Speed commands that drive blind (no lane): an arc with branch and radius_m, else straight.
BLIND_SPEEDS = ("creep", "reverse")


def check_parking_place(place: str) -> str:
    """The place if known, else ValueError naming the field and the choices."""
    if place not in PARKING_PLACES:
        raise ValueError("parking_place: expected one of %s, got %r" % (", ".join(PARKING_PLACES), place))
    return place


def parking_event(place: str) -> Optional[str]:
    """The event that names the parking place `place` (None for "auto": the place seen)."""
    return None if check_parking_place(place) == AUTO else "parking_" + place


def manoeuvre_speed_mps(speed: str, park_speed_mps: float) -> Optional[float]:
    """The target speed [m/s] of a manoeuvre speed command (creep: +park_speed_mps, reverse:
    -park_speed_mps), None for the other commands."""
    return {"creep": park_speed_mps, "reverse": -park_speed_mps}.get(speed)


# --- the bay-parking area as seen (parking_place "auto") ----------------------------------------


class BayFinder:
    """The bays of the bay-parking area along the road, from what conde_tracking sees: the lines
    across the road on its right (LaneMeasurement.bay_line_distances_m) and the boxes right of the
    road (its obstacle_* fields), each sighting put at its place along the road (the distance
    driven, travelled_m, plus its distance ahead).  Pure Python.

    A line is known after min_sightings sightings within line_merge_m of each other (their mean).
    Neighbouring known lines bay_width_m apart enclose a bay; twice that apart, two bays (the
    dashed divider between them is often unseen at a distance, or hidden behind a box).  A bay is
    occupied when a box's near edge was seen between its lines."""

    def __init__(self, bay_width_m: Tuple[float, float] = (0.6, 0.95), line_merge_m: float = 0.1,
                 min_sightings: int = 2, box_side_y_m: float = -0.5):
        self.bay_width_m = bay_width_m
        self.line_merge_m = line_merge_m
        self.min_sightings = min_sightings
        self.box_side_y_m = box_side_y_m  # boxes with their left edge right of this are off the road [m]
        self._lines: List[List[float]] = []  # [sum of positions, count] per line
        self._boxes_m: List[float] = []  # near edges of boxes off the road, along the road [m]

    def on_lines(self, travelled_m: float, distances_m) -> None:
        for d in distances_m:
            at_m = travelled_m + float(d)
            for line in self._lines:
                if abs(line[0] / line[1] - at_m) <= self.line_merge_m:
                    line[0] += at_m
                    line[1] += 1
                    break
            else:
                self._lines.append([at_m, 1])

    def on_box(self, travelled_m: float, distance_m: float, y_max_m: float) -> None:
        """A box seen distance_m ahead [m], its left edge at y_max_m in base_footprint [m]."""
        if y_max_m < self.box_side_y_m:
            self._boxes_m.append(travelled_m + distance_m)

    @property
    def lines_m(self) -> List[float]:
        """The known lines along the road [m], in order."""
        return sorted(s / n for s, n in self._lines if n >= self.min_sightings)

    @property
    def any_line_seen(self) -> bool:
        return bool(self._lines)

    def bays(self) -> List[Tuple[float, float, bool]]:
        """(start [m], end [m], occupied) of each bay along the road, in order."""
        lo, hi = self.bay_width_m
        out = []
        lines = self.lines_m
        for a, b in zip(lines, lines[1:]):
            if lo <= b - a <= hi:
                edges = [a, b]
            elif 2 * lo <= b - a <= 2 * hi:
                edges = [a, 0.5 * (a + b), b]
            else:
                continue
            for s, e in zip(edges, edges[1:]):
                out.append((s, e, any(s <= box <= e for box in self._boxes_m)))
        return out

    def free_bay(self) -> Optional[Tuple[float, float]]:
        """(start, end) along the road [m] of the first free bay, None if none is known."""
        for s, e, occupied in self.bays():
            if not occupied:
                return s, e
        return None


def bay_entry_lead_m(spec, state: str, event: str = "bay_entry_near") -> Optional[float]:
    """How far before a bay's centre line the robot is when `event` fires in `state` [m]: the
    straight distances of the states it leads to (through distance_elapsed) up to the first arc,
    plus that arc's radius (a 90-degree turn into the bay ends on its centre line).  None when the
    state does not listen to the event or the chain has no arc."""
    target = spec.states[state].transitions.get(event) if state in spec.states else None
    lead_m, seen = 0.0, set()
    while target in spec.states and target not in seen:
        seen.add(target)
        command = spec.states[target].command
        if command.radius_m is not None:
            return lead_m + command.radius_m
        lead_m += command.distance_m or 0.0
        target = spec.states[target].transitions.get("distance_elapsed")
    return None
