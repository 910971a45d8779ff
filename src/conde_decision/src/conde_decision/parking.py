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

import math
from typing import List, Optional, Tuple

from conde_common.bay_pairing import BAY_WIDTH_M, pair_bays

#: parking_place "auto": the place is the parking area the cameras show (no place event).
AUTO = "auto"
#: The places, each with the event that sends go_to_parking toward it; "auto": the place seen.
PARKING_PLACES = ("auto", "parallel", "bay_north", "bay_south")
#: Speed commands that drive blind (no lane): an arc with branch and radius_m, else straight.
BLIND_SPEEDS = ("creep", "reverse")
#: The events a state listens to while it looks for a parking place (conde_tracking's search is on).
PARKING_SEARCH_EVENTS = ("parking_bays_seen", "parking_parallel", "bay_entry_near", "park_entry_near")


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
    A box sighting joins a box when its near end lies within box_merge_m of that box's nearest
    sighting (or beyond it, up to box_merge_m past its farthest); a box is known after
    min_sightings sightings, its near end the nearest sighting (while the robot passes a box its
    near face leaves the view, and the nearest point seen lies farther on).  The bays and which
    holds a box: conde_common.bay_pairing (the rule conde_tracking's bays_between shares)."""

    def __init__(self, bay_width_m: Tuple[float, float] = BAY_WIDTH_M, line_merge_m: float = 0.1,
                 min_sightings: int = 2, box_side_y_m: float = -0.5, box_merge_m: float = 0.3):
        self.bay_width_m = bay_width_m
        self.line_merge_m = line_merge_m
        self.min_sightings = min_sightings
        self.box_side_y_m = box_side_y_m  # boxes with their left edge right of this are off the road [m]
        self.box_merge_m = box_merge_m
        self._lines: List[List[float]] = []  # [sum of positions, count] per line
        self._boxes: List[List[float]] = []  # near ends seen along the road, per box [m]

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
        if not y_max_m < self.box_side_y_m:
            return
        at_m = travelled_m + distance_m
        for nears in self._boxes:
            if min(nears) - self.box_merge_m <= at_m <= max(nears) + self.box_merge_m:
                nears.append(at_m)
                return
        self._boxes.append([at_m])

    @property
    def lines_m(self) -> List[float]:
        """The known lines along the road [m], in order."""
        return sorted(s / n for s, n in self._lines if n >= self.min_sightings)

    @property
    def boxes_m(self) -> List[float]:
        """The near ends of the known boxes off the road, along the road [m], in order."""
        return sorted(min(nears) for nears in self._boxes if len(nears) >= self.min_sightings)

    def bays(self) -> List[Tuple[float, float, bool]]:
        """(start [m], end [m], occupied) of each bay along the road, in order."""
        return pair_bays(self.lines_m, self.boxes_m, self.bay_width_m)

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


# --- the parallel bay as seen ---------------------------------------------------------------------


class ParallelGapFinder:
    """Where to park in the parallel bay, from what conde_tracking sees: where the bay's straight
    part begins (LaneMeasurement.parallel_bay_start_m) and the boxes standing in it (obstacle_*
    fields with obstacle_far_distances_m), each sighting put at its place along the road (the
    distance driven, travelled_m, plus its distance ahead).  Pure Python.

    The bay's start is known after min_sightings sightings within merge_m of each other (their
    median).  A box sighting joins a box when its near end lies within box_merge_m before that
    box's nearest sighting or up to its far end; a box is known after min_sightings sightings, its
    near end the nearest sighting (the near face goes out of view while the robot passes, and the
    nearest point seen then lies farther on), its far end the median of the far ends seen.

    The free stretches run from the bay's start or a box's far end to the next box's near end;
    the robot parks in the middle of the first at least min_gap_m long.  With no box beyond the
    bay's start (P1) the middle of the bay lies bay_centre_m beyond its start (half its straight
    part)."""

    def __init__(self, min_gap_m: float = 0.9, bay_centre_m: float = 1.53, merge_m: float = 0.1,
                 box_merge_m: float = 0.3, min_sightings: int = 2, box_side_y_m: float = -0.5):
        self.min_gap_m = min_gap_m
        self.bay_centre_m = bay_centre_m
        self.merge_m = merge_m
        self.box_merge_m = box_merge_m
        self.min_sightings = min_sightings
        self.box_side_y_m = box_side_y_m  # boxes with their left edge right of this are off the road [m]
        self._starts_m: List[List[float]] = []  # sightings of the bay's start, in clusters
        self._boxes: List[Tuple[List[float], List[float]]] = []  # (near ends, far ends) seen, per box

    def on_bay_start(self, travelled_m: float, distance_m: float) -> None:
        """The bay's straight part seen to begin distance_m ahead [m] (NaN: not seen)."""
        if not math.isfinite(distance_m):
            return
        at_m = travelled_m + distance_m
        for cluster in self._starts_m:
            if abs(_median(cluster) - at_m) <= self.merge_m:
                cluster.append(at_m)
                return
        self._starts_m.append([at_m])

    def on_box(self, travelled_m: float, near_m: float, far_m: float, y_max_m: float) -> None:
        """A box seen from near_m to far_m ahead [m] (far_m NaN: its far end not seen), its left
        edge at y_max_m in base_footprint [m]."""
        if not y_max_m < self.box_side_y_m:
            return
        near_at, far_at = travelled_m + near_m, travelled_m + far_m
        for nears, fars in self._boxes:
            reach_m = max([min(nears) + self.box_merge_m] + [f for f in fars])
            if min(nears) - self.box_merge_m <= near_at <= reach_m:
                nears.append(near_at)
                if math.isfinite(far_at):
                    fars.append(far_at)
                return
        self._boxes.append(([near_at], [far_at] if math.isfinite(far_at) else []))

    @property
    def bay_start_m(self) -> Optional[float]:
        """The bay's start along the road [m], None while not known."""
        known = [c for c in self._starts_m if len(c) >= self.min_sightings]
        return _median(max(known, key=len)) if known else None

    def boxes(self) -> List[Tuple[float, Optional[float]]]:
        """(near end, far end or None) along the road [m] of each known box, in order."""
        out = [(min(nears), _median(fars) if fars else None) for nears, fars in self._boxes
               if len(nears) >= self.min_sightings]
        return sorted(out)

    def target_m(self) -> Optional[float]:
        """Where along the road [m] the middle of the free stretch to park in lies, None while not known."""
        start = self.bay_start_m
        from_bay_start = start is not None
        for near, far in self.boxes():
            if start is not None and near - start >= self.min_gap_m:
                return 0.5 * (start + near)
            if far is None:
                return None
            start, from_bay_start = (far if start is None else max(start, far)), False
        if from_bay_start:
            return start + self.bay_centre_m
        return None


def _median(values: List[float]) -> float:
    v = sorted(values)
    n = len(v)
    return v[n // 2] if n % 2 else 0.5 * (v[n // 2 - 1] + v[n // 2])


def manoeuvre_advance_m(spec, state: str) -> Optional[float]:
    """How far ahead of where `state` begins [m] (along the heading there) the blind manoeuvre
    ends that begins there and runs through distance_elapsed: straights and arcs (branch,
    radius_m) driven forward (creep) or backward (reverse).  None if the chain does not end in a
    state without a distance (e.g. parked) or holds a command that is not a manoeuvre."""
    x_m, y_m, heading, seen = 0.0, 0.0, 0.0, set()
    while state in spec.states and state not in seen:
        seen.add(state)
        command = spec.states[state].command
        if command.distance_m is None:
            return x_m
        if command.speed not in BLIND_SPEEDS:
            return None
        d = command.distance_m * (-1.0 if command.speed == "reverse" else 1.0)
        if command.radius_m is not None and command.branch in ("left", "right"):
            k = (1.0 if command.branch == "left" else -1.0) / command.radius_m  # curvature [1/m]
            x_m += (math.sin(heading + k * d) - math.sin(heading)) / k
            y_m += (math.cos(heading) - math.cos(heading + k * d)) / k
            heading += k * d
        else:
            x_m += d * math.cos(heading)
            y_m += d * math.sin(heading)
        state = spec.states[state].transitions.get("distance_elapsed")
    return None
