"""Keyboard teleop of an Ackermann car (pure Python; ackermann_teleop is the node).

Keys (arrow keys or WASD):
  up / w       faster by one speed step (from reverse: toward 0 first)
  down / s     slower by one speed step; below 0 the car reverses
  left / a     steer one step to the left
  right / d    steer one step to the right
  c            steering straight
  space        stop (speed 0, steering kept)
  q, Ctrl-C    quit (the node sends a stop first)

The command is held: the node re-sends it at its rate, so the car keeps going until the speed
is set back to 0. Units: m/s, rad (+ = left).
"""

from dataclasses import dataclass
from typing import List, Optional

from conde_common.rate_limit import clamp

ACTIONS = {
    "\x1b[A": "faster", "w": "faster", "W": "faster",
    "\x1b[B": "slower", "s": "slower", "S": "slower",
    "\x1b[D": "left", "a": "left", "A": "left",
    "\x1b[C": "right", "d": "right", "D": "right",
    "c": "centre", "C": "centre",
    " ": "stop",
    "q": "quit", "Q": "quit", "\x03": "quit",
}

HELP = ("arrows or w/s: speed, a/d: steering, c: straight, space: stop, q: quit")


@dataclass(frozen=True)
class TeleopLimits:
    """Steps per key press and limits of the held command (all > 0)."""

    speed_step_mps: float = 0.25  # per faster / slower key [m/s]
    steering_step_rad: float = 0.05  # per left / right key [rad]
    max_speed_mps: float = 2.0  # forward [m/s]
    max_reverse_speed_mps: float = 1.0  # backward, as a positive number [m/s]
    max_steering_rad: float = 0.4189  # either side [rad] (24 degrees)

    def __post_init__(self):
        for name in ("speed_step_mps", "steering_step_rad", "max_speed_mps", "max_reverse_speed_mps",
                     "max_steering_rad"):
            value = getattr(self, name)
            if not (isinstance(value, (int, float)) and value > 0 and value < float("inf")):
                raise ValueError("%s: must be a number > 0, got %r" % (name, value))


@dataclass(frozen=True)
class DriveCommand:
    speed_mps: float = 0.0
    steering_rad: float = 0.0


def split_keys(text: str) -> List[str]:
    """Splits what the terminal sent into keys; an arrow key is one three-character key."""
    keys, i = [], 0
    while i < len(text):
        if text[i] == "\x1b" and text[i + 1:i + 2] in ("[", "O") and i + 2 < len(text):
            keys.append("\x1b[" + text[i + 2])  # ESC O A (application mode) = ESC [ A
            i += 3
        else:
            keys.append(text[i])
            i += 1
    return keys


def apply_key(key: str, command: DriveCommand, limits: TeleopLimits) -> Optional[DriveCommand]:
    """The command after a key (unknown keys leave it unchanged); None: quit."""
    action = ACTIONS.get(key)
    speed, steering = command.speed_mps, command.steering_rad
    if action == "quit":
        return None
    if action == "faster":
        speed += limits.speed_step_mps
    elif action == "slower":
        speed -= limits.speed_step_mps
    elif action == "left":
        steering += limits.steering_step_rad
    elif action == "right":
        steering -= limits.steering_step_rad
    elif action == "centre":
        steering = 0.0
    elif action == "stop":
        speed = 0.0
    # round away the float residue of repeated steps (0.1 + 0.2 ...), to a micrometre per second
    speed = round(clamp(speed, -limits.max_reverse_speed_mps, limits.max_speed_mps), 6)
    steering = round(clamp(steering, -limits.max_steering_rad, limits.max_steering_rad), 6)
    return DriveCommand(speed, steering)


def status_line(command: DriveCommand) -> str:
    return "speed %+5.2f m/s  steering %+6.3f rad" % (command.speed_mps, command.steering_rad)
