"""What the referee knows of a challenge's course, from the track geometry and the challenge's
resolved layout (conde_worlds): painted lines, road surface, start line and loop gates, the
immobilisation zones before the crosswalk, the parking bays, the objects' footprints and the V1
signs, all on the challenge's track (its track seed: the nominal or a varied track, conde_worlds
track_variation). Pure Python (numpy), no ROS. World frame: x east, y north [m]; headings [rad]."""
import functools
import math
from dataclasses import dataclass
from typing import Dict, List, Optional, Tuple

import numpy as np

from conde_worlds import challenge_objects as co
from conde_worlds import track_geometry as tg
from conde_worlds.path_primitives import NO_BOX, boxes_overlap, points_box
from conde_worlds.challenge_world import layout, objects_of
from conde_worlds.challenges import load_challenges, parse_seed
from conde_worlds.track_variation import track_dimensions
from conde_worlds.sign_names import SIGNS

#: The start/finish line across the straight, 0.21 m behind the crosswalk (as conde_eval's lap
#: timer), on the nominal track (Course.start_line_y_m: on the course's track).
START_LINE_Y_M = -0.55
#: Loop gates: from the loop centre across the road at the loop's far end (north: top, south:
#: bottom), on the nominal track (Course.gate_length_m: on the course's track).
GATE_LENGTH_M = tg.LOOP_RADIUS + tg.ROAD_HALF_WIDTH + 0.5
#: Painted lines that count as "touching a line" while driving: the road's solid boundary lines.
BOUNDARY_PREFIXES = ("central_west", "central_east", "north_loop_island", "north_loop_outer",
                     "south_loop_island", "south_loop_outer")
#: Parking lines (touching one while parking is penalised); the bays' west border is their entry.
PARKING_PREFIXES = ("bay_border_north", "bay_border_south", "bay_border_east", "bay_divider", "parallel_parking")


@dataclass(frozen=True)
class Obstacle:
    """An object's footprint: a convex polygon (N, 2) [m], and its bottom above the floor [m]."""

    name: str
    polygon: np.ndarray
    z_bottom_m: float
    x_m: float = 0.0  # where the object stands in the layout: its centre [m] and yaw [rad]
    y_m: float = 0.0
    yaw_rad: float = 0.0
    dynamic: bool = False  # can be pushed (has a mass)

    def moved_to(self, x_m: float, y_m: float, yaw_rad: float) -> np.ndarray:
        """The footprint with the object at (x_m, y_m, yaw_rad) instead of its layout pose."""
        d = yaw_rad - self.yaw_rad
        c, s = math.cos(d), math.sin(d)
        rel = self.polygon - (self.x_m, self.y_m)
        return np.column_stack([x_m + c * rel[:, 0] - s * rel[:, 1], y_m + s * rel[:, 0] + c * rel[:, 1]])


def _box_polygon(obj) -> Tuple[np.ndarray, float]:
    (x, y, z), (roll, yaw) = obj["pose"]["xyz"], obj["pose"]["rpy"][0::2]
    sx, sy, sz = obj["size_m"]
    if abs(abs(roll) - math.pi / 2) < 0.1:  # stood on its side (the sign faces): y and z swap
        sy, sz = sz, sy
    c, s = math.cos(yaw), math.sin(yaw)
    hx, hy = sx / 2.0, sy / 2.0
    poly = np.array([(x + c * u - s * v, y + s * u + c * v) for u, v in ((hx, hy), (-hx, hy), (-hx, -hy), (hx, -hy))])
    return poly, z - sz / 2.0


def obstacles_of(objects) -> List[Obstacle]:
    out = []
    for obj in objects:
        if obj["shape"] == "box":
            poly, z0 = _box_polygon(obj)
        elif obj["shape"] in ("cone", "cylinder"):
            (x, y, z), r = obj["pose"]["xyz"], obj["radius_m"]
            a = np.linspace(0.0, 2 * math.pi, 12, endpoint=False)
            poly, z0 = np.column_stack([x + r * np.cos(a), y + r * np.sin(a)]), z - obj["length_m"] / 2.0
        else:
            continue
        (x, y, _), yaw = obj["pose"]["xyz"], obj["pose"].get("rpy", [0.0, 0.0, 0.0])[2]
        out.append(Obstacle(obj["name"], poly, z0, x, y, yaw, not obj.get("static", True)))
    return out


class Course:
    """One challenge's course. Build with :meth:`from_layout` or :meth:`from_summary`."""

    def __init__(self, challenge: str, features: dict, seed: int, time_limit_s: float, track_seed: int = 0):
        self.challenge = challenge
        self.features = features
        self.seed = seed
        self.time_limit_s = time_limit_s
        self.track_seed = track_seed
        #: The track's measures (conde_worlds.track_variation.TrackDimensions).
        self.dims = track_dimensions(track_seed)
        self.track = tg.build_track(self.dims)
        self.start_line_y_m = self.dims.map_xy(self.dims.x_ref_m, START_LINE_Y_M)[1]
        self.gate_length_m = self.dims.loop_radius_m + self.dims.road_half_width_m + 0.5
        objects, _ = objects_of(features, seed, self.dims)
        self.obstacles = obstacles_of(objects)
        self.boundary_lines = [s for s in self.track.strokes if s.name.startswith(BOUNDARY_PREFIXES)]
        self.parking_lines = [s for s in self.track.strokes if s.name.startswith(PARKING_PREFIXES)]
        self.occupied_bay: Optional[str] = features.get("occupied_bay")
        self.signs: List[Tuple[float, float, str]] = []
        if "signs" in features:
            order = co.sign_order(SIGNS, seed if features["signs"] == "shuffle" else 0)
            self.signs = [(x, y, sign) for (x, y, _), sign in zip(co.sign_poses(self.dims), order)]

    @classmethod
    def from_layout(cls, challenge: str, variant: Optional[str] = None, seed: int = 0, challenges_path=None,
                    track_seed: int = 0):
        challenges = load_challenges(challenges_path)
        name, _variant, seed, features = layout(challenges, challenge, variant, seed)
        return cls(name, features, seed, challenges.challenges[name].time_limit_s, parse_seed(track_seed, "track seed"))

    @classmethod
    def from_summary(cls, summary: dict):
        """From generate_challenge's challenge.yaml (the parameter /challenge/summary_file); a
        summary without track_seed is on the nominal track."""
        return cls(summary["challenge"], summary["features"], int(summary["seed"]), float(summary["time_limit_s"]),
                   parse_seed(summary.get("track_seed", 0), "track seed"))

    @property
    def kind(self) -> str:
        """'driving' (D*), 'parking' (P*, B*) or 'signs' (V1)."""
        return {"P": "parking", "B": "parking", "V": "signs"}.get(self.challenge[:1], "driving")

    # --- queries on world points (N, 2) ------------------------------------------------------------

    def touches(self, points, strokes, skip=None) -> List[str]:
        """Names of the strokes that any of the points lies on (within half the line width of the
        stroke's centre, inside a painted interval). skip(stroke, points) -> mask of points to ignore."""
        pts = np.asarray(points, dtype=float)
        hit = []
        if not len(pts):
            return hit
        near = points_box(pts)
        for stroke in strokes:
            if not boxes_overlap(painted_box(stroke), near):
                continue  # no point can be on this stroke
            s, lat = stroke.prim.project(pts)
            on = np.abs(lat) <= stroke.width / 2.0
            if not on.any():
                continue
            painted = np.zeros(len(pts), dtype=bool)
            for a, b in stroke.intervals:
                painted |= (s >= a) & (s <= b)
            on &= painted
            if skip is not None:
                on &= ~skip(stroke, pts)
            if on.any():
                hit.append(stroke.name)
        return hit

    def on_surface(self, points) -> np.ndarray:
        """Points on the road or in a parking area."""
        pts = np.asarray(points, dtype=float)
        (bx0, bx1), (by0, by1) = self.dims.bay_area_x_m, self.dims.bay_area_y_m
        in_bays = (pts[:, 0] >= bx0) & (pts[:, 0] <= bx1) & (pts[:, 1] >= by0) & (pts[:, 1] <= by1)
        return self.track.on_road(pts) | self.track.in_parallel_parking(pts) | in_bays

    def loop_position(self, x: float, y: float) -> Optional[Tuple[str, float, float]]:
        """(loop, angle along its 270-degree arc [deg], radius [m]) of a point on a loop's road
        (challenge_objects.loop_point's angles), or None off the loops' arcs."""
        for loop in ("north", "south"):
            cx, cy = co.loop_centre(loop, self.dims)
            r = math.hypot(x - cx, y - cy)
            if abs(r - self.dims.loop_radius_m) > self.dims.road_half_width_m:
                continue
            angle = math.degrees(math.atan2((y - cy) if loop == "north" else (cy - y), x - cx)) % 360.0
            if angle <= 270.0:
                return loop, angle, r
        return None

    def free_bays(self) -> Dict[str, tuple]:
        """{name: ((x0, x1), (y0, y1))} of the places the robot may park in [m]: the parallel bay in
        the P challenges, the free bays in the B ones, and in the D challenges (a parking order on the
        panel, e.g. at the end of D2's second lap) any parking place: both bays and the parallel bay."""
        if self.challenge.startswith("P"):
            return {"parallel": co.parallel_bay(self.dims)}
        bays = {k: v for k, v in co.parking_bays(self.dims).items() if k != self.occupied_bay}
        if self.challenge.startswith("D"):
            bays["parallel"] = co.parallel_bay(self.dims)
        return bays


@functools.lru_cache(maxsize=1024)
def painted_box(stroke) -> Tuple[float, float, float, float]:
    """A box (x_min, y_min, x_max, y_max) holding every point that Course.touches counts as on the
    stroke: within half its width of the centre, between its first and last painted s."""
    if not stroke.intervals:
        return NO_BOX
    return stroke.prim.box(min(a for a, _ in stroke.intervals), max(b for _, b in stroke.intervals),
                           stroke.width / 2.0)


def inside_box(points, box) -> np.ndarray:
    (x0, x1), (y0, y1) = box
    p = np.asarray(points, dtype=float)
    return (p[:, 0] >= x0) & (p[:, 0] <= x1) & (p[:, 1] >= y0) & (p[:, 1] <= y1)


def polygons_overlap(a: np.ndarray, b: np.ndarray) -> bool:
    """Separating-axis test of two convex polygons (N, 2), (M, 2)."""
    for poly in (a, b):
        edges = np.roll(poly, -1, axis=0) - poly
        for ex, ey in edges:
            axis = np.array([-ey, ex])
            pa, pb = a @ axis, b @ axis
            if pa.max() < pb.min() or pb.max() < pa.min():
                return False
    return True
