"""Key map of the keyboard teleop: key presses -> the commanded (linear [m/s], angular [rad/s]).

Pure Python, no ROS.  Each press of a speed key moves one command by one step; the command stays
until the next key, so a node republishes it.  Keys (a key is the text one key press sends, an
arrow key being its escape sequence):

  i or Up      linear  + linear_step_mps     (at most  max_linear_mps)
  , or Down    linear  - linear_step_mps     (at least -max_linear_mps; below 0 = backwards)
  j or Left    angular + angular_step_radps  (at most  max_angular_radps; + = counter-clockwise)
  l or Right   angular - angular_step_radps  (at least -max_angular_radps)
  k or Space   both 0
  q or Ctrl-C  quit (the node stops the robot)

The arrow keys, Space and q are those of the original conde_key_teleop (Up/Down/Left/Right, the
stop key of its "turbo" mode, quit); i j k l , is the usual ROS teleop layout.  Other keys are
ignored.  The commands are whole multiples of the step (counted as integers, so stepping up and
back down returns to exactly 0), clipped to the limit when the limit is not a multiple.
"""

import enum
import math
from dataclasses import dataclass, fields
from typing import Optional, Tuple


class Action(enum.Enum):
    FASTER = "faster"  # linear + one step
    SLOWER = "slower"  # linear - one step
    LEFT = "left"  # angular + one step
    RIGHT = "right"  # angular - one step
    STOP = "stop"  # both 0
    QUIT = "quit"


# Arrow keys send ESC [ A..D, or ESC O A..D when the terminal is in "application cursor" mode.
UP_KEYS = ("\x1b[A", "\x1bOA")
DOWN_KEYS = ("\x1b[B", "\x1bOB")
RIGHT_KEYS = ("\x1b[C", "\x1bOC")
LEFT_KEYS = ("\x1b[D", "\x1bOD")
CTRL_C = "\x03"  # arrives as a key only where the terminal does not turn it into SIGINT

KEY_ACTIONS = {
    **{key: Action.FASTER for key in ("i",) + UP_KEYS},
    **{key: Action.SLOWER for key in (",",) + DOWN_KEYS},
    **{key: Action.LEFT for key in ("j",) + LEFT_KEYS},
    **{key: Action.RIGHT for key in ("l",) + RIGHT_KEYS},
    "k": Action.STOP,
    " ": Action.STOP,
    "q": Action.QUIT,
    CTRL_C: Action.QUIT,
}


@dataclass(frozen=True)
class TeleopSettings:
    """Steps and limits.  The initial values are the defaults (chosen for Conde: the driving
    stack's cruise speed is 0.5 m/s; 1.5 rad/s at 0.5 m/s is a 0.33 m radius, tighter than the
    track's tightest lane, 0.61 m)."""

    linear_step_mps: float = 0.1  # change of linear.x per key press [m/s]
    angular_step_radps: float = 0.25  # change of angular.z per key press [rad/s]
    max_linear_mps: float = 0.5  # |linear.x| limit [m/s]
    max_angular_radps: float = 1.5  # |angular.z| limit [rad/s]


SETTING_NAMES = tuple(f.name for f in fields(TeleopSettings))
_STEP_LIMITS = (("linear_step_mps", "max_linear_mps"), ("angular_step_radps", "max_angular_radps"))


class SettingsError(ValueError):
    """A setting that cannot be used: `name` is the setting, `reason` what is wrong with it."""

    def __init__(self, name: str, reason: str):
        super().__init__("%s: %s" % (name, reason))
        self.name = name
        self.reason = reason


def validate(settings: TeleopSettings) -> None:
    """Raises SettingsError for the first setting that is not a finite number > 0, or a step
    larger than its limit."""
    for name in SETTING_NAMES:
        value = getattr(settings, name)
        if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value) or value <= 0:
            raise SettingsError(name, "expected a number > 0, got %r" % (value,))
    for step_name, limit_name in _STEP_LIMITS:
        step, limit = getattr(settings, step_name), getattr(settings, limit_name)
        if step > limit:
            raise SettingsError(step_name, "must not exceed %s (%r), got %r" % (limit_name, limit, step))


def _steps_to_limit(limit: float, step: float) -> int:
    """How many steps reach the limit: limit / step, rounded up unless it is a whole number
    (up to rounding error, so that 0.3 / 0.1 = 2.9999999999999996 counts as 3)."""
    ratio = limit / step
    nearest = round(ratio)
    return int(nearest) if abs(ratio - nearest) < 1e-9 else math.ceil(ratio)


def _clip(value: float, limit: float) -> float:
    return max(-limit, min(limit, value))


class TeleopKeymap:
    """The commanded velocity, changed one key press at a time; starts at (0, 0)."""

    def __init__(self, settings: TeleopSettings = TeleopSettings()):
        validate(settings)
        self.settings = settings
        self._max_linear_steps = _steps_to_limit(settings.max_linear_mps, settings.linear_step_mps)
        self._max_angular_steps = _steps_to_limit(settings.max_angular_radps, settings.angular_step_radps)
        self._linear_steps = 0
        self._angular_steps = 0

    @property
    def command(self) -> Tuple[float, float]:
        """(linear [m/s], angular [rad/s], + = counter-clockwise)."""
        s = self.settings
        return (_clip(self._linear_steps * s.linear_step_mps, s.max_linear_mps),
                _clip(self._angular_steps * s.angular_step_radps, s.max_angular_radps))

    def press(self, key: str) -> Optional[Action]:
        """Applies one key press; returns its action (QUIT changes nothing here), or None for a
        key that is not in the map (ignored)."""
        action = KEY_ACTIONS.get(key)
        if action is Action.FASTER:
            self._linear_steps = min(self._linear_steps + 1, self._max_linear_steps)
        elif action is Action.SLOWER:
            self._linear_steps = max(self._linear_steps - 1, -self._max_linear_steps)
        elif action is Action.LEFT:
            self._angular_steps = min(self._angular_steps + 1, self._max_angular_steps)
        elif action is Action.RIGHT:
            self._angular_steps = max(self._angular_steps - 1, -self._max_angular_steps)
        elif action is Action.STOP:
            self.stop()
        return action

    def stop(self) -> None:
        self._linear_steps = 0
        self._angular_steps = 0

    def describe_command(self) -> str:
        linear_mps, angular_radps = self.command
        return "linear %+.2f m/s, angular %+.2f rad/s" % (linear_mps, angular_radps)

    def help_text(self) -> str:
        s = self.settings
        return "\n".join((
            "Conde keyboard teleop: one key at a time, no Enter.",
            "  i or Up      faster forward    linear  +%g m/s (up to %g m/s)" % (s.linear_step_mps, s.max_linear_mps),
            "  , or Down    slower/backwards  linear  -%g m/s (down to -%g m/s)" % (s.linear_step_mps,
                                                                                    s.max_linear_mps),
            "  j or Left    turn left         angular +%g rad/s (up to %g rad/s)" % (s.angular_step_radps,
                                                                                     s.max_angular_radps),
            "  l or Right   turn right        angular -%g rad/s (down to -%g rad/s)" % (s.angular_step_radps,
                                                                                        s.max_angular_radps),
            "  k or Space   stop",
            "  q or Ctrl-C  quit (sends a stop first)",
            "Other keys are ignored.",
        ))
