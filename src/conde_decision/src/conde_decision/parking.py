"""Parking: which place the robot parks in, and the speeds of the parking manoeuvres.  Pure Python.

The manoeuvres themselves are states of config/conde_states.yaml (the park_* and bay_* blocks):
blind arcs and straights driven forward (speed ``creep``) or backward (speed ``reverse``) at
park_speed_mps for known distances, measured by odometry from where the lane was left.  The
place is chosen by the parameter parking_place (not perceived yet): the state go_to_parking
leaves on the event of that place (parking_parallel, parking_bay_north, parking_bay_south),
which fires in every step while the current state listens to it.
"""

from typing import Optional

#: The places, each with the event that sends go_to_parking toward it.
PARKING_PLACES = ("parallel", "bay_north", "bay_south")
#: Speed commands that drive blind (no lane): an arc with branch and radius_m, else straight.
BLIND_SPEEDS = ("creep", "reverse")


def check_parking_place(place: str) -> str:
    """The place if known, else ValueError naming the field and the choices."""
    if place not in PARKING_PLACES:
        raise ValueError("parking_place: expected one of %s, got %r" % (", ".join(PARKING_PLACES), place))
    return place


def parking_event(place: str) -> str:
    """The event that names the parking place `place`."""
    return "parking_" + check_parking_place(place)


def manoeuvre_speed_mps(speed: str, park_speed_mps: float) -> Optional[float]:
    """The target speed [m/s] of a manoeuvre speed command (creep: +park_speed_mps, reverse:
    -park_speed_mps), None for the other commands."""
    return {"creep": park_speed_mps, "reverse": -park_speed_mps}.get(speed)
