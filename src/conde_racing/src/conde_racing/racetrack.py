"""Metric geometry of the racetrack (conde_worlds/worlds/racetrack.world.yaml).

The circuit is a centre line of straights and circular arcs, driven counter-clockwise, with
walls 0.7 m to each side of it (a 1.4 m wide corridor for 1/10-scale cars). It starts at the
world origin heading +x (east) along the 7 m main straight, turns left four times around a
rectangle of about 11 x 6.6 m, and has an S-shaped dip in the back straight (left, right, right,
left) so that a driver has to turn both ways. Lengths in metres, angles in radians, positions
in the world frame (x east, y north); s is the arc length along the centre line from the origin.

Everything the other files need comes from here: the world's walls and spawn poses, the floor
texture, the lap timer's start/finish line and checkpoints (racetrack_world.py writes them).
"""

import math
from dataclasses import dataclass
from typing import List, Sequence, Tuple

import numpy as np
from conde_worlds.path_primitives import Path

HALF_WIDTH_M = 0.7          # centre line to the face of each wall
WALL_THICKNESS_M = 0.05
WALL_HEIGHT_M = 0.25        # above the LiDAR (0.15 m) of the F1/10 car
WALL_MAX_SAGITTA_M = 0.01   # curved walls: chord boxes stay within this of the true arc


@dataclass(frozen=True)
class Straight:
    length_m: float


@dataclass(frozen=True)
class Arc:
    radius_m: float
    angle_rad: float        # signed: + = left (counter-clockwise) turn


QUARTER = math.pi / 2
SEGMENTS = (
    Straight(7.0),           # main straight, start/finish line near its end
    Arc(1.6, QUARTER),       # turn 1
    Straight(2.0),
    Arc(1.6, QUARTER),       # turn 2
    Straight(0.6),
    Arc(1.3, QUARTER),       # the dip: left ...
    Arc(1.3, -QUARTER),      # ... right
    Straight(0.6),
    Arc(1.3, -QUARTER),      # ... right
    Arc(1.3, QUARTER),       # ... left
    Straight(0.6),
    Arc(1.6, QUARTER),       # turn 3
    Straight(2.0),
    Arc(1.6, QUARTER),       # turn 4, back to the origin
)

START_LINE_S_M = 6.5        # start/finish line across the main straight (x = 6.5 m)
CHECKPOINT_S_M = (12.0, 22.0)  # lines a lap must cross in order (the lap timer's checkpoints)

# Starting grid: two staggered columns behind the start line, 16 slots. Slot 0 (pole) is on the
# left (inside of turn 1); each next slot is `GRID_PITCH_M` further back on the other side.
GRID_SLOTS = 16
GRID_FRONT_GAP_M = 0.1      # pole car's nose to the line
CAR_NOSE_M = 0.44           # F1/10 car: nose ahead of base_footprint (rear-axle centre)
GRID_PITCH_M = 0.35
GRID_LATERAL_M = 0.3


@dataclass(frozen=True)
class Pose2D:
    x_m: float
    y_m: float
    yaw_rad: float


def _pieces(segments: Sequence) -> List[Tuple[float, ...]]:
    """The segments as pieces of path_primitives' Path.chain."""
    return [(seg.length_m,) if isinstance(seg, Straight) else (seg.radius_m, seg.angle_rad) for seg in segments]


def _pose(prim, s_m: float, yaw_near_rad: float) -> Pose2D:
    """Pose at arc length s_m along one primitive, its yaw the branch nearest yaw_near_rad (the
    yaw stays continuous along the closed line: 2 pi after the lap)."""
    x, y = prim.point(s_m)
    yaw_rad = yaw_near_rad + math.remainder(float(prim.heading(s_m)) - yaw_near_rad, 2 * math.pi)
    return Pose2D(float(x), float(y), yaw_rad)


class CentreLine:
    """The closed centre line: poses by arc length, sampling, projection of points onto it."""

    def __init__(self, segments: Sequence = SEGMENTS, start: Pose2D = Pose2D(0.0, 0.0, 0.0)):
        self.segments = tuple(segments)
        self.path = Path.chain(start.x_m, start.y_m, start.yaw_rad, _pieces(self.segments))
        self.start_yaw_rad: List[float] = []  # unwrapped yaw at each segment's start
        yaw = start.yaw_rad
        for seg in self.segments:
            self.start_yaw_rad.append(yaw)
            yaw += 0.0 if isinstance(seg, Straight) else seg.angle_rad
        ends = [(p.point(p.length), y) for p, y in zip(self.path.prims, self.start_yaw_rad[1:] + [yaw])]
        self.starts: List[Pose2D] = [start] + [Pose2D(float(x), float(y), w) for (x, y), w in ends[:-1]]
        self.start_s: List[float] = [float(s) for s in self.path.starts]
        self.length_m = self.path.length
        (x, y), _ = ends[-1]
        self.end = Pose2D(float(x), float(y), yaw)
        self._dense = None

    def pose_at(self, s_m: float) -> Pose2D:
        i, along_m = self.path.locate(s_m % self.length_m)
        i = int(i)
        prim = self.path.prims[i]
        return _pose(prim, min(float(along_m), prim.length), self.start_yaw_rad[i])

    def curvature_at(self, s_m: float) -> float:
        """Signed curvature [1/m] (+ = turning left)."""
        return self.path.prims[int(self.path.locate(s_m % self.length_m)[0])].curvature

    def point_at(self, s_m: float, lateral_m: float = 0.0) -> Tuple[float, float]:
        """Point at arc length s, `lateral_m` to the left of the centre line (negative: right)."""
        p = self.pose_at(s_m)
        return (p.x_m - lateral_m * math.sin(p.yaw_rad), p.y_m + lateral_m * math.cos(p.yaw_rad))

    def line_across(self, s_m: float, half_length_m: float = HALF_WIDTH_M):
        """A line across the track at s, from wall to wall: ((x, y) right end, (x, y) left end),
        right and left as seen facing the race direction."""
        return self.point_at(s_m, -half_length_m), self.point_at(s_m, half_length_m)

    def sample(self, spacing_m: float) -> np.ndarray:
        """Points every ~spacing_m along the whole line (first at s = 0, the end not repeated):
        array of rows (s, x, y, yaw)."""
        n = max(3, int(math.ceil(self.length_m / spacing_m)))
        rows = []
        for k in range(n):
            s = k * self.length_m / n
            p = self.pose_at(s)
            rows.append((s, p.x_m, p.y_m, p.yaw_rad))
        return np.array(rows)

    def project(self, x_m: float, y_m: float) -> Tuple[float, float]:
        """(s, lateral offset [m], + = left of the centre line) of the nearest centre-line point,
        to about 5 mm."""
        if self._dense is None:
            self._dense = self.sample(0.005)
        d = self._dense
        i = int(np.argmin((d[:, 1] - x_m) ** 2 + (d[:, 2] - y_m) ** 2))
        s, x, y, yaw = d[i]
        lateral = -(x_m - x) * math.sin(yaw) + (y_m - y) * math.cos(yaw)
        return float(s), float(lateral)


@dataclass(frozen=True)
class WallBox:
    name: str
    centre_xy_m: Tuple[float, float]
    yaw_rad: float
    length_m: float


def wall_boxes(line: CentreLine = None) -> List[WallBox]:
    """Static boxes along both sides of the centre line: one per straight and side, and chords of
    each arc, so that the wall faces stay within WALL_MAX_SAGITTA_M of the true curve. Every box
    overlaps its neighbours by a wall thickness, which closes the wedges between chords."""
    line = line or CentreLine()
    offset = HALF_WIDTH_M + WALL_THICKNESS_M / 2
    boxes = []
    for index, (seg, prim, start) in enumerate(zip(line.segments, line.path.prims, line.starts)):
        for side_name, side in (("left", 1.0), ("right", -1.0)):
            if isinstance(seg, Straight):
                pieces = 1
            else:
                wall_radius = seg.radius_m - math.copysign(1.0, seg.angle_rad) * side * offset
                max_step = 2.0 * math.acos(1.0 - WALL_MAX_SAGITTA_M / wall_radius)
                pieces = int(math.ceil(abs(seg.angle_rad) / max_step))
            for k in range(pieces):
                a, b = (_pose(prim, prim.length * k / pieces, start.yaw_rad),
                        _pose(prim, prim.length * (k + 1) / pieces, start.yaw_rad))
                ax, ay = a.x_m - side * offset * math.sin(a.yaw_rad), a.y_m + side * offset * math.cos(a.yaw_rad)
                bx, by = b.x_m - side * offset * math.sin(b.yaw_rad), b.y_m + side * offset * math.cos(b.yaw_rad)
                boxes.append(WallBox(
                    name="wall_%02d_%s_%02d" % (index, side_name, k),
                    centre_xy_m=((ax + bx) / 2, (ay + by) / 2),
                    yaw_rad=math.atan2(by - ay, bx - ax),
                    length_m=math.hypot(bx - ax, by - ay) + WALL_THICKNESS_M))
    return boxes


def grid_poses(line: CentreLine = None, slots: int = GRID_SLOTS) -> List[Pose2D]:
    """Start poses (base_footprint of each car) of the starting grid, pole first."""
    line = line or CentreLine()
    poses = []
    for k in range(slots):
        s = START_LINE_S_M - GRID_FRONT_GAP_M - CAR_NOSE_M - k * GRID_PITCH_M
        lateral = GRID_LATERAL_M if k % 2 == 0 else -GRID_LATERAL_M
        x, y = line.point_at(s, lateral)
        poses.append(Pose2D(x, y, line.pose_at(s).yaw_rad))
    return poses


def extent_m(line: CentreLine = None, margin_m: float = 0.0):
    """((x_min, x_max), (y_min, y_max)) of the area between the outer walls, plus a margin."""
    line = line or CentreLine()
    pts = []
    for s, _, _, _ in line.sample(0.05):
        for lateral in (-(HALF_WIDTH_M + WALL_THICKNESS_M), HALF_WIDTH_M + WALL_THICKNESS_M):
            pts.append(line.point_at(s, lateral))
    pts = np.array(pts)
    return ((float(pts[:, 0].min()) - margin_m, float(pts[:, 0].max()) + margin_m),
            (float(pts[:, 1].min()) - margin_m, float(pts[:, 1].max()) + margin_m))
