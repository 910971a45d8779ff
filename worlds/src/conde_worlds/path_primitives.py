"""2-D path primitives: straight segments and circular arcs, and chains of them, parametrised by
arc length s [m].  Pure Python + numpy, no ROS.

Metres and radians in a plane frame (x, y), headings measured from +x counter-clockwise.  The
competition track (track_geometry) and conde_racing's racetrack build their lines from these;
point(), heading() and project() take scalars or arrays of s / points."""

import functools
import math
from dataclasses import dataclass
from typing import List, Sequence, Tuple

import numpy as np

TWO_PI = 2.0 * math.pi


def as_points(points) -> np.ndarray:
    """Any (x, y) or sequence of them as an (N, 2) float array."""
    p = np.asarray(points, dtype=float)
    return p.reshape(-1, 2)


def rotated(p, angle: float, origin) -> Tuple[float, float]:
    """p rotated by angle [rad] (counter-clockwise), then moved by origin."""
    c, s = math.cos(angle), math.sin(angle)
    return (origin[0] + c * p[0] - s * p[1], origin[1] + s * p[0] + c * p[1])


# Margin [m] added to every reach box (box()) against rounding in project().
BOX_MARGIN_M = 1e-6


# A box that overlaps no box (boxes_overlap).
NO_BOX = (math.inf, math.inf, -math.inf, -math.inf)


def points_box(points) -> Tuple[float, float, float, float]:
    """(x_min, y_min, x_max, y_max) of the finite points of an (N, 2) array (NO_BOX if none: a
    point with a NaN coordinate is on no primitive)."""
    finite = np.isfinite(points).all(axis=1)
    if not finite.all():
        if not finite.any():
            return NO_BOX
        points = points[finite]
    lo, hi = points.min(axis=0), points.max(axis=0)
    return float(lo[0]), float(lo[1]), float(hi[0]), float(hi[1])


def boxes_overlap(a, b) -> bool:
    """Whether two (x_min, y_min, x_max, y_max) boxes share a point (edges count)."""
    return a[0] <= b[2] and b[0] <= a[2] and a[1] <= b[3] and b[1] <= a[3]


def plain_float(v, nd=6) -> float:
    """A plain Python float rounded to nd decimals (for YAML export)."""
    return round(float(v), nd) + 0.0  # + 0.0 turns -0.0 into 0.0


def plain_point(p, nd=6) -> List[float]:
    return [plain_float(v, nd) for v in p]


@dataclass(frozen=True)
class Segment:
    """Straight segment from p0 to p1, parametrised by arc length s in [0, length]."""

    p0: Tuple[float, float]
    p1: Tuple[float, float]

    kind = "line"

    @staticmethod
    def from_pose(x_m: float, y_m: float, yaw_rad: float, length_m: float) -> "Segment":
        """The segment of length_m that starts at (x_m, y_m) heading yaw_rad."""
        return Segment((x_m, y_m), (x_m + length_m * math.cos(yaw_rad), y_m + length_m * math.sin(yaw_rad)))

    @property
    def length(self) -> float:
        return math.hypot(self.p1[0] - self.p0[0], self.p1[1] - self.p0[1])

    @property
    def curvature(self) -> float:
        return 0.0

    @property
    def direction(self) -> np.ndarray:
        d = np.subtract(self.p1, self.p0)
        return d / np.hypot(d[0], d[1])

    def point(self, s) -> np.ndarray:
        s = np.asarray(s, dtype=float)
        return np.asarray(self.p0) + s[..., None] * self.direction

    def heading(self, s) -> np.ndarray:
        d = self.direction
        return np.full(np.shape(s), math.atan2(d[1], d[0]))

    def project(self, points) -> Tuple[np.ndarray, np.ndarray]:
        """Arc length of the perpendicular foot (not clamped) and lateral offset (+ = left)."""
        p = as_points(points) - np.asarray(self.p0)
        d = self.direction
        return p @ d, d[0] * p[:, 1] - d[1] * p[:, 0]

    @functools.lru_cache(maxsize=4096)
    def box(self, s0: float, s1: float, lateral_m: float) -> Tuple[float, float, float, float]:
        """A box holding every point that project() puts at s0 <= s <= s1 and |lateral| <= lateral_m
        (the rectangle's corners are within the box of its end points grown by lateral_m); NO_BOX for
        a segment of zero length, whose project() gives NaN."""
        if self.length == 0.0:
            return NO_BOX
        ux, uy = (self.p1[0] - self.p0[0]) / self.length, (self.p1[1] - self.p0[1]) / self.length
        xs = (self.p0[0] + s0 * ux, self.p0[0] + s1 * ux)
        ys = (self.p0[1] + s0 * uy, self.p0[1] + s1 * uy)
        grow = lateral_m + BOX_MARGIN_M
        return min(xs) - grow, min(ys) - grow, max(xs) + grow, max(ys) + grow

    def offset(self, d: float) -> "Segment":
        """The parallel segment d to the left (negative d: to the right)."""
        u = self.direction
        n = np.array([-u[1], u[0]]) * d
        return Segment(tuple(np.add(self.p0, n)), tuple(np.add(self.p1, n)))

    def reversed(self) -> "Segment":
        return Segment(self.p1, self.p0)

    def sub(self, s0: float, s1: float) -> "Segment":
        return Segment(tuple(self.point(s0)), tuple(self.point(s1)))

    def mirrored_y(self) -> "Segment":
        return Segment((self.p0[0], -self.p0[1]), (self.p1[0], -self.p1[1]))

    def transformed(self, angle: float, origin) -> "Segment":
        return Segment(rotated(self.p0, angle, origin), rotated(self.p1, angle, origin))

    def to_dict(self) -> dict:
        return {"type": "line", "from": plain_point(self.p0), "to": plain_point(self.p1)}


@dataclass(frozen=True)
class Arc:
    """Circular arc: centre, radius, start angle and signed sweep (+ = counter-clockwise)."""

    centre: Tuple[float, float]
    radius: float
    start: float
    sweep: float

    kind = "arc"

    @staticmethod
    def from_pose(x_m: float, y_m: float, yaw_rad: float, radius_m: float, turn_rad: float) -> "Arc":
        """The arc of radius_m that starts at (x_m, y_m) heading yaw_rad and turns through
        turn_rad (+ = left, counter-clockwise)."""
        side = math.copysign(1.0, turn_rad)  # centre of the circle: left (+1) or right (-1)
        centre = (x_m - side * radius_m * math.sin(yaw_rad), y_m + side * radius_m * math.cos(yaw_rad))
        return Arc(centre, radius_m, yaw_rad - side * math.pi / 2.0, turn_rad)

    @property
    def sense(self) -> float:
        return 1.0 if self.sweep > 0 else -1.0

    @property
    def length(self) -> float:
        return self.radius * abs(self.sweep)

    @property
    def curvature(self) -> float:
        """Signed curvature [1/m] (+ = turning left)."""
        return self.sense / self.radius

    def angle(self, s) -> np.ndarray:
        return self.start + self.sense * np.asarray(s, dtype=float) / self.radius

    def point(self, s) -> np.ndarray:
        a = self.angle(s)
        return np.stack([self.centre[0] + self.radius * np.cos(a),
                         self.centre[1] + self.radius * np.sin(a)], axis=-1)

    def heading(self, s) -> np.ndarray:
        return self.angle(s) + self.sense * math.pi / 2.0

    def project(self, points) -> Tuple[np.ndarray, np.ndarray]:
        """Arc length of the radial foot and lateral offset (+ = left of the direction of travel).

        Angles outside the sweep map to s < 0 or s > length, split half-way round the gap."""
        p = as_points(points) - np.asarray(self.centre)
        dist = np.hypot(p[:, 0], p[:, 1])
        rel = np.mod(self.sense * (np.arctan2(p[:, 1], p[:, 0]) - self.start), TWO_PI)
        span = abs(self.sweep)
        rel = np.where(rel > span + (TWO_PI - span) / 2.0, rel - TWO_PI, rel)
        return rel * self.radius, self.sense * (self.radius - dist)

    def box(self, s0: float, s1: float, lateral_m: float) -> Tuple[float, float, float, float]:
        """A box holding every point that project() puts at s0 <= s <= s1 and |lateral| <= lateral_m:
        the whole circle's, grown by lateral_m (whatever the s range)."""
        reach = self.radius + lateral_m + BOX_MARGIN_M
        return self.centre[0] - reach, self.centre[1] - reach, self.centre[0] + reach, self.centre[1] + reach

    def offset(self, d: float) -> "Arc":
        r = self.radius - self.sense * d
        if r <= 0:
            raise ValueError("offset %.3f m collapses an arc of radius %.3f m" % (d, self.radius))
        return Arc(self.centre, r, self.start, self.sweep)

    def reversed(self) -> "Arc":
        return Arc(self.centre, self.radius, self.start + self.sweep, -self.sweep)

    def sub(self, s0: float, s1: float) -> "Arc":
        return Arc(self.centre, self.radius, float(self.angle(s0)), self.sense * (s1 - s0) / self.radius)

    def mirrored_y(self) -> "Arc":
        return Arc((self.centre[0], -self.centre[1]), self.radius, -self.start, -self.sweep)

    def transformed(self, angle: float, origin) -> "Arc":
        return Arc(rotated(self.centre, angle, origin), self.radius, self.start + angle, self.sweep)

    def to_dict(self) -> dict:
        return {"type": "arc", "centre": plain_point(self.centre), "radius_m": plain_float(self.radius, 6),
                "start_rad": plain_float(self.start, 6), "sweep_rad": plain_float(self.sweep, 6)}


class Path:
    """A chain of primitives parametrised by the total arc length."""

    def __init__(self, prims: Sequence):
        self.prims = list(prims)
        lengths = [p.length for p in self.prims]
        self.starts = np.concatenate([[0.0], np.cumsum(lengths)[:-1]])
        self.length = float(sum(lengths))

    @staticmethod
    def chain(x_m: float, y_m: float, yaw_rad: float, pieces: Sequence[Tuple[float, ...]]) -> "Path":
        """The path from the pose (x_m, y_m, yaw_rad) through pieces, each (length_m,) for a
        straight or (radius_m, turn_rad) for an arc (+ = left), each starting where the last ends."""
        prims = []
        for piece in pieces:
            prim = Segment.from_pose(x_m, y_m, yaw_rad, *piece) if len(piece) == 1 else \
                Arc.from_pose(x_m, y_m, yaw_rad, *piece)
            prims.append(prim)
            (x_m, y_m), yaw_rad = (float(v) for v in prim.point(prim.length)), float(prim.heading(prim.length))
        return Path(prims)

    def offset(self, d: float) -> "Path":
        return Path([p.offset(d) for p in self.prims])

    def reversed(self) -> "Path":
        return Path([p.reversed() for p in reversed(self.prims)])

    def mirrored_y(self) -> "Path":
        return Path([p.mirrored_y() for p in self.prims])

    def locate(self, s):
        """(index of the primitive, arc length along it) for path arc lengths s (clamped to the
        first and last primitive)."""
        s = np.asarray(s, dtype=float)
        i = np.clip(np.searchsorted(self.starts, s, side="right") - 1, 0, len(self.prims) - 1)
        return i, s - self.starts[i]

    def point(self, s) -> np.ndarray:
        i, ls = self.locate(s)
        out = np.empty(np.shape(s) + (2,))
        for k, p in enumerate(self.prims):
            m = i == k
            if np.any(m):
                out[m] = p.point(ls[m])
        return out

    def heading(self, s) -> np.ndarray:
        i, ls = self.locate(s)
        out = np.empty(np.shape(s))
        for k, p in enumerate(self.prims):
            m = i == k
            if np.any(m):
                out[m] = p.heading(ls[m])
        return out
