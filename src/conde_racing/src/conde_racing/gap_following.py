"""Follow-the-gap driving from a planar LiDAR scan (pure Python + numpy; gap_follower is the node).

Per scan:
1. Ranges: +inf and NaN (no return) count as `max_range_m`, everything is capped there.
2. Disparity extension: where two neighbouring beams differ by more than `disparity_m` (the edge
   of a wall, a corner, another car), the nearer range is copied over the beams on the far side
   that a car-width-plus-margin disc at that range would cover, so the car never aims at a
   point it would only reach by clipping the edge.
3. Target: within the field of view, the beams that reach (within 0.1 m) the farthest extended
   range; the middle of the widest run of them.
4. Steering: pure pursuit to the point on the target beam at `lookahead_m` (or nearer, where
   the beam ends): curvature k = 2 y / (x^2 + y^2) in base_footprint (rear-axle centre), steering
   angle atan(wheelbase k), clipped to +-max_steering_rad.
5. Speed: the lowest of `max_speed_mps`, sqrt(max_lateral_accel / |curvature of the steering|)
   and sqrt(2 braking_decel (clearance - stop_distance)) where clearance is the free distance
   ahead of the car's nose within its width (plus `path_margin_m` a side); at least
   `min_speed_mps`.
6. Blocked (clearance below `stop_distance_m`): back up at `reverse_speed_mps` for
   `reverse_time_s`, steering away from the more open side (larger mean range) so that the
   nose swings toward it.

Frames: scan angles from the LiDAR's +x (forward), counter-clockwise; the LiDAR is assumed
aligned with the car, `laser_x_m` ahead of base_footprint on its centre line. Units: m, rad, s,
m/s. Defaults are the F1/10 car of conde_description (robots/f1tenth.urdf.xacro).
"""

import math
from dataclasses import dataclass, fields
from typing import Sequence

import numpy as np


@dataclass(frozen=True)
class GapFollowerConfig:
    wheelbase_m: float = 0.33
    laser_x_m: float = 0.27             # LiDAR ahead of base_footprint
    nose_x_m: float = 0.44              # front of the car ahead of base_footprint
    car_half_width_m: float = 0.155
    path_margin_m: float = 0.05         # added to each side of the car for the clearance ahead
    max_steering_rad: float = 0.4189
    field_of_view_rad: float = math.pi  # beams within +-half of this of straight ahead are targets
    max_range_m: float = 5.0
    disparity_m: float = 0.3
    safety_margin_m: float = 0.25       # added to the half width by the disparity extension
    lookahead_m: float = 0.8           # about 2.5 wheelbases: steers close to the target angle
    max_speed_mps: float = 2.0
    min_speed_mps: float = 0.4
    max_lateral_accel_mps2: float = 3.0
    braking_decel_mps2: float = 3.0
    stop_distance_m: float = 0.1        # clearance ahead of the nose below which the car backs up
    reverse_speed_mps: float = 0.5
    reverse_time_s: float = 1.0

    def __post_init__(self):
        for f in fields(self):
            value = getattr(self, f.name)
            if not (isinstance(value, (int, float)) and math.isfinite(value)):
                raise ValueError("%s: expected a finite number, got %r" % (f.name, value))
            if f.name != "laser_x_m" and value <= 0:
                raise ValueError("%s: must be > 0, got %r" % (f.name, value))
        if self.min_speed_mps > self.max_speed_mps:
            raise ValueError("min_speed_mps (%g) must not exceed max_speed_mps (%g)"
                             % (self.min_speed_mps, self.max_speed_mps))
        if not self.max_steering_rad < math.pi / 2 or not self.field_of_view_rad <= 2 * math.pi:
            raise ValueError("max_steering_rad must be < pi/2 and field_of_view_rad <= 2 pi")


@dataclass(frozen=True)
class Decision:
    speed_mps: float
    steering_rad: float
    target_angle_rad: float     # NaN while backing up
    clearance_m: float          # free distance ahead of the nose, within the car's width
    reversing: bool


class GapFollower:
    """The driver; keeps only the backing-up state between scans."""

    def __init__(self, config: GapFollowerConfig = GapFollowerConfig()):
        self.config = config
        self._reverse_until_s = -math.inf
        self._reverse_steering_rad = 0.0

    def reset(self) -> None:
        self._reverse_until_s = -math.inf

    def clean_ranges(self, ranges: Sequence[float]) -> np.ndarray:
        r = np.asarray(ranges, dtype=float).copy()
        r[np.isnan(r) | np.isposinf(r)] = self.config.max_range_m
        r[r < 0] = 0.0
        return np.minimum(r, self.config.max_range_m)

    def extend_disparities(self, r: np.ndarray, angle_increment_rad: float) -> np.ndarray:
        """Step 2: the ranges with the nearer side of every disparity widened (see the module)."""
        c = self.config
        out = r.copy()
        edges = np.nonzero(np.abs(np.diff(r)) > c.disparity_m)[0]
        reach = c.car_half_width_m + c.safety_margin_m
        for i in edges:
            near = min(r[i], r[i + 1])
            half_angle = math.atan2(reach, near) if near > 0 else math.pi / 2
            n = int(math.ceil(half_angle / abs(angle_increment_rad)))
            if r[i] < r[i + 1]:
                out[i + 1:i + 1 + n] = np.minimum(out[i + 1:i + 1 + n], near)
            else:
                lo = max(0, i + 1 - n)
                out[lo:i + 1] = np.minimum(out[lo:i + 1], near)
        return out

    def clearance_m(self, r: np.ndarray, angles: np.ndarray) -> float:
        """Free distance ahead of the nose within the car's width plus path_margin_m each side.
        Points beside the car (behind its nose) do not count: a wall the car passes closely is no
        obstacle ahead."""
        c = self.config
        ahead = r * np.cos(angles) + c.laser_x_m - c.nose_x_m
        within_width = np.abs(r * np.sin(angles)) <= c.car_half_width_m + c.path_margin_m
        in_path = (ahead >= 0) & within_width & (r > 0)
        return float(ahead[in_path].min()) if in_path.any() else c.max_range_m + c.laser_x_m - c.nose_x_m

    def target(self, extended: np.ndarray, angles: np.ndarray):
        """Step 3: (angle [rad], extended range [m]) of the target beam."""
        c = self.config
        candidates = np.abs(angles) <= c.field_of_view_rad / 2
        if not candidates.any():
            return 0.0, 0.0
        best = extended[candidates].max()
        good = candidates & (extended >= best - 0.1)
        # widest run of consecutive good beams
        padded = np.concatenate(([False], good, [False])).astype(int)
        starts = np.nonzero(np.diff(padded) == 1)[0]
        ends = np.nonzero(np.diff(padded) == -1)[0]      # exclusive
        k = int(np.argmax(ends - starts))
        i = (starts[k] + ends[k] - 1) // 2
        return float(angles[i]), float(extended[i])

    def steering_to(self, angle_rad: float, range_m: float) -> float:
        """Step 4: pure-pursuit steering angle to the point on a beam."""
        c = self.config
        d = max(min(range_m, c.lookahead_m), 0.05)
        x = c.laser_x_m + d * math.cos(angle_rad)
        y = d * math.sin(angle_rad)
        curvature = 2.0 * y / (x * x + y * y)
        return max(-c.max_steering_rad, min(c.max_steering_rad, math.atan(c.wheelbase_m * curvature)))

    def speed_for(self, steering_rad: float, clearance_m: float) -> float:
        """Step 5."""
        c = self.config
        curvature = abs(math.tan(steering_rad)) / c.wheelbase_m
        v = c.max_speed_mps
        if curvature > 0:
            v = min(v, math.sqrt(c.max_lateral_accel_mps2 / curvature))
        v = min(v, math.sqrt(2.0 * c.braking_decel_mps2 * max(0.0, clearance_m - c.stop_distance_m)))
        return max(v, c.min_speed_mps)

    def decide(self, ranges: Sequence[float], angle_min_rad: float, angle_increment_rad: float,
               time_s: float) -> Decision:
        """The command for one scan taken at `time_s` (any clock that only moves forward)."""
        c = self.config
        r = self.clean_ranges(ranges)
        angles = angle_min_rad + angle_increment_rad * np.arange(r.size)
        clearance = self.clearance_m(r, angles)
        if time_s < self._reverse_until_s:
            return Decision(-c.reverse_speed_mps, self._reverse_steering_rad, math.nan, clearance, True)
        angle, reach = self.target(self.extend_disparities(r, angle_increment_rad), angles)
        steering = self.steering_to(angle, reach)
        if clearance < c.stop_distance_m:
            self._reverse_until_s = time_s + c.reverse_time_s
            # backing up with the wheels turned away from the more open side swings the nose
            # toward it (the raw ranges: close up, the disparity extension hides every gap)
            in_view = np.abs(angles) <= c.field_of_view_rad / 2
            left, right = r[in_view & (angles > 0)], r[in_view & (angles < 0)]
            open_side = (left.mean() if left.size else 0.0) - (right.mean() if right.size else 0.0)
            self._reverse_steering_rad = -math.copysign(c.max_steering_rad, open_side) if open_side else 0.0
            return Decision(-c.reverse_speed_mps, self._reverse_steering_rad, math.nan, clearance, True)
        return Decision(self.speed_for(steering, clearance), steering, angle, clearance, False)
