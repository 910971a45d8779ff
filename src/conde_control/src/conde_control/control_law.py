"""Lane-following control law of a differential-drive robot, with speed and acceleration limits.

Pure Python, no ROS.  Input: the fields of conde_msgs/ControlReference (measured lateral offset
and heading error relative to the lane, their references, the wanted forward speed).  Output:
(v [m/s], omega [rad/s]) for geometry_msgs/Twist.

Sign conventions (those of the message):
  offset  + = robot left of the lane centre          [m]
  heading + = robot points left of the lane direction  [rad]
  omega   + = turn left (counter-clockwise seen from above)  [rad/s]

Law (kinematic unicycle on a straight lane: d offset/dt = v sin(heading), d heading/dt = omega):

    omega = v * path_curvature
            - offset_gain_per_m2 * v * (offset - offset_ref)
            - heading_gain_per_m * |v| * (heading - heading_ref)

path_curvature (feed-forward, 0 when following a lane) lets the decision drive an arc of known
radius where the lane cannot be measured (a 90-degree turn at a junction).

Both terms scale with the speed, so the path the robot drives to get back to its lane is the
same at every speed: linearised, the offset obeys  e'' + k_h e' + k_o e = 0  with derivatives
along the travelled distance (natural "frequency" sqrt(k_o) [1/m], damping k_h / (2 sqrt(k_o))).
Using v for the offset term and |v| for the heading term keeps that true when reversing.  A robot
that stands still does not turn on measurement noise.

Limits, in this order: the wanted speed is clipped to +-max_linear_mps and approached at
max_linear_accel_mps2; omega is computed from that limited speed, clipped to +-max_angular_radps
and approached at max_angular_accel_radps2.  What the model ignores: wheel slip, and the lane's
curvature while following a lane (path_curvature 0 there: a curve of curvature k leaves a steady
offset of about k / offset_gain_per_m2 toward its outside).
"""

import math
import os
from dataclasses import dataclass, fields
from typing import Tuple

from conde_common.config_files import parse_yaml, read_text
from conde_common.rate_limit import approach, clip


@dataclass(frozen=True)
class ControlConfig:
    """Gains and limits.  The initial values are the defaults of config/control.yaml."""

    offset_gain_per_m2: float = 36.0  # [rad/s per m of offset per m/s of speed]
    heading_gain_per_m: float = 10.0  # [rad/s per rad of heading error per m/s of speed]
    max_linear_mps: float = 1.0  # |v| limit [m/s]
    max_angular_radps: float = 3.0  # |omega| limit [rad/s]
    max_linear_accel_mps2: float = 1.0  # |dv/dt| limit [m/s^2]
    max_angular_accel_radps2: float = 8.0  # |domega/dt| limit [rad/s^2]


#: Keys that are limits (must be > 0); the gains must be >= 0.
_LIMIT_KEYS = ("max_linear_mps", "max_angular_radps", "max_linear_accel_mps2", "max_angular_accel_radps2")


class ConfigError(ValueError):
    """A control configuration that cannot be used; the message names the file and the key."""


def load_config(path: str) -> ControlConfig:
    """Reads a control YAML file strictly: unknown keys, non-numbers, negative gains and
    non-positive limits are errors naming the file and the key.  Missing keys keep their
    defaults."""
    data = parse_yaml(read_text(path, ConfigError, "the control configuration"), path, ConfigError, "YAML error")
    return config_from_dict(data if data is not None else {}, path)


def config_from_dict(data, source: str) -> ControlConfig:
    """The checks of load_config on already parsed data; `source` names it in messages."""
    if not isinstance(data, dict):
        raise ConfigError("%s: expected a mapping of gains and limits, got %s" % (source, type(data).__name__))
    known = [f.name for f in fields(ControlConfig)]
    values = {}
    for key, value in data.items():
        if key not in known:
            raise ConfigError("%s: unknown key '%s' (expected one of: %s)" % (source, key, ", ".join(known)))
        if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
            raise ConfigError("%s: %s: expected a finite number, got %r" % (source, key, value))
        if key in _LIMIT_KEYS and value <= 0:
            raise ConfigError("%s: %s: a limit must be > 0, got %g" % (source, key, value))
        if key not in _LIMIT_KEYS and value < 0:
            raise ConfigError("%s: %s: a gain must be >= 0, got %g" % (source, key, value))
        values[key] = float(value)
    return ControlConfig(**values)


def default_config_path() -> str:
    """config/control.yaml of the conde_control package (found with rospkg)."""
    import rospkg  # only needed here: the pure law and the loader work without ROS

    return os.path.join(rospkg.RosPack().get_path("conde_control"), "config", "control.yaml")


@dataclass(frozen=True)
class Reference:
    """The fields of conde_msgs/ControlReference that the law uses (units in the names)."""

    lateral_offset_m: float = 0.0
    lateral_offset_ref_m: float = 0.0
    heading_error_rad: float = 0.0
    heading_ref_rad: float = 0.0
    linear_velocity_mps: float = 0.0
    path_curvature_per_m: float = 0.0


class LaneFollowingController:
    """Turns references into (v, omega) commands, one call per control period.

    `update(ref, dt_s)` follows the lane; `brake(dt_s)` decelerates to a stand within the
    limits (used when no fresh reference is available); `reset()` forgets the last command
    (the robot is assumed to stand)."""

    def __init__(self, config: ControlConfig = ControlConfig()):
        self.config = config
        self.v_mps = 0.0
        self.omega_radps = 0.0

    def reset(self) -> None:
        self.v_mps = 0.0
        self.omega_radps = 0.0

    def update(self, ref, dt_s: float) -> Tuple[float, float]:
        """One step toward the command the law asks for; `ref` is any object with the fields of
        Reference (a ControlReference message works).  Non-finite fields raise ValueError."""
        curvature_per_m = getattr(ref, "path_curvature_per_m", 0.0)
        values = [ref.lateral_offset_m, ref.lateral_offset_ref_m, ref.heading_error_rad,
                  ref.heading_ref_rad, ref.linear_velocity_mps, curvature_per_m]
        if not all(math.isfinite(x) for x in values):
            raise ValueError("reference has a non-finite field: %r" % (values,))
        c = self.config
        v = self._next_v(clip(ref.linear_velocity_mps, c.max_linear_mps), dt_s)
        offset_error_m = ref.lateral_offset_m - ref.lateral_offset_ref_m
        heading_error_rad = ref.heading_error_rad - ref.heading_ref_rad
        omega_target = (v * curvature_per_m - c.offset_gain_per_m2 * v * offset_error_m
                        - c.heading_gain_per_m * abs(v) * heading_error_rad)
        return v, self._next_omega(omega_target, dt_s)

    def brake(self, dt_s: float) -> Tuple[float, float]:
        """One step toward standing still (v = 0, omega = 0) within the acceleration limits."""
        v = self._next_v(0.0, dt_s)
        return v, self._next_omega(0.0, dt_s)

    def _check_dt(self, dt_s: float) -> None:
        if not (math.isfinite(dt_s) and dt_s >= 0.0):
            raise ValueError("dt_s must be finite and >= 0, got %r" % (dt_s,))

    def _next_v(self, target_mps: float, dt_s: float) -> float:
        self._check_dt(dt_s)
        self.v_mps = approach(self.v_mps, target_mps, self.config.max_linear_accel_mps2 * dt_s)
        return self.v_mps

    def _next_omega(self, target_radps: float, dt_s: float) -> float:
        c = self.config
        target = clip(target_radps, c.max_angular_radps)
        self.omega_radps = approach(self.omega_radps, target, c.max_angular_accel_radps2 * dt_s)
        return self.omega_radps
