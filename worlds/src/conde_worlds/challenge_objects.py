"""World objects of the challenges, computed from the track geometry.

Pure Python, no ROS.  Each builder returns world-file object mappings (docs/world_format.md).
Positions on a loop are given by ``angle_deg``, the progress along the loop's 270-degree arc
from the end of the central straight (0 = where the straight ends, at the top for the north loop
and at the bottom for the south loop), so the same numbers describe both loops (the south loop
is the mirror image of the north loop in y).

Dimensions (the rules' facts as the original simulator modelled them): obstacle boxes
0.6 x 0.6 x 0.2 m, green, 10 kg; cones 0.15 m base, 0.23 m tall, orange, 4 kg; traffic-sign
faces 0.305 m square with their centre 1.0 m above the floor.  The tunnel's size is not in the
rules found: ours is 1.0 m high inside, its walls 0.15 m outside the painted lines.
"""

import math
import random
from typing import Dict, List, Sequence, Tuple

from . import track_geometry as tg
from .challenges import ChallengeError
from .track_variation import NOMINAL, TrackDimensions

OBSTACLE_SIZE_M = (0.6, 0.6, 0.2)
OBSTACLE_MASS_KG = 10.0
GREEN = [0.0, 1.0, 0.0]
CONE_BASE_RADIUS_M = 0.075
CONE_HEIGHT_M = 0.23
CONE_MASS_KG = 4.0
ORANGE = [1.0, 0.27, 0.0]
#: Cones of the working zone stand this far inside the closed lane from the lane divider's
#: centre, so that their bases (radius 0.075 m) stay off the open lane.
CONE_DIVIDER_CLEARANCE_M = 0.1
CONE_SPACING_M = 0.45
TAPER_DEG = 20.0
TUNNEL_HEIGHT_M = 1.0
TUNNEL_WALL_M = 0.05
TUNNEL_ROOF_M = 0.03
TUNNEL_MARGIN_M = 0.15
TUNNEL_SEGMENT_DEG = 10.0
TUNNEL_GREY = [0.45, 0.45, 0.45]
#: Under the tunnel's roof the cameras see the scene at this fraction of its brightness (our
#: choice: dark enough that lane tracking must cope with it, bright enough to see the lines).
TUNNEL_LIGHT = 0.35
#: The light region's outline follows the walls' centre lines in steps of this many degrees.
TUNNEL_LIGHT_STEP_DEG = 2.0
SIGN_SIZE_M = 0.305
SIGN_THICKNESS_M = 0.01
SIGN_CENTRE_HEIGHT_M = 1.0
#: Keep random obstacles this far [deg of loop arc] from the working zone and the tunnel.
RANDOM_CLEARANCE_DEG = 15.0
RANDOM_ATTEMPTS = 200

#: Radius of the lane divider (road reference line) of the loops, and of the lane centres, on
#: the nominal track (the functions below give them for any track's measures).
DIVIDER_R = tg.LOOP_RADIUS
LANE_R = {"inner": tg.LOOP_RADIUS - tg.LANE_OFFSET, "outer": tg.LOOP_RADIUS + tg.LANE_OFFSET}
ISLAND_LINE_R = tg.LOOP_RADIUS - tg.LINE_SPACING
OUTER_LINE_R = tg.LOOP_RADIUS + tg.LINE_SPACING


def lane_radii(dims: TrackDimensions = NOMINAL) -> Dict[str, float]:
    """{'inner', 'outer'}: radius of the loops' lane centres [m] (LANE_R of the track dims)."""
    return {"inner": dims.loop_radius_m - dims.lane_offset_m, "outer": dims.loop_radius_m + dims.lane_offset_m}


def island_line_radius(dims: TrackDimensions = NOMINAL) -> float:
    return dims.loop_radius_m - dims.line_spacing_m


def outer_line_radius(dims: TrackDimensions = NOMINAL) -> float:
    return dims.loop_radius_m + dims.line_spacing_m


#: The twelve sign positions of the original simulator's V1 world: (x, y) [m] and yaw [rad];
#: the face points along Rz(yaw) * (0, -1, 0).  All are off the road of our track.
SIGN_POSES = [
    (2.8, 5.0, 0.0), (0.0, 8.3, 1.5708), (-3.6, 5.0, 3.1416), (-3.6, -5.0, 3.1416),
    (0.0, -8.3, -1.5708), (2.8, -5.0, 0.0), (0.0, 4.0, 1.5708), (-1.6, 5.0, 0.0),
    (0.0, 6.3, -1.5708), (0.6, -5.0, 3.1416), (0.0, -6.2, 1.5708), (-1.6, -5.0, 0.0),
]


def _r(v, nd=4):
    return round(float(v), nd)


def loop_centre(loop: str, dims: TrackDimensions = NOMINAL) -> Tuple[float, float]:
    cy = dims.loop_centre_y_m
    return (dims.loop_centre_x_m, cy if loop == "north" else -cy)


def loop_point(loop: str, angle_deg: float, radius_m: float,
               dims: TrackDimensions = NOMINAL) -> Tuple[float, float, float]:
    """(x, y, heading of the loop arc's direction of progress [rad]) on a loop circle."""
    cx, cy = loop_centre(loop, dims)
    a = math.radians(angle_deg)
    if loop == "north":
        return cx + radius_m * math.cos(a), cy + radius_m * math.sin(a), a + 0.5 * math.pi
    return cx + radius_m * math.cos(a), cy - radius_m * math.sin(a), -(a + 0.5 * math.pi)


def _obj(name, shape, xyz, yaw=0.0, color=None, **extra):
    o = {"name": name, "shape": shape}
    o.update({k: v for k, v in extra.items() if k in ("size_m", "radius_m", "length_m")})
    o["pose"] = {"xyz": [_r(c) for c in xyz], "rpy": [_r(c) for c in extra.get("rpy", (0.0, 0.0, yaw))]}
    if color is not None:
        o["color_rgb"] = color
    o.update({k: v for k, v in extra.items() if k in ("texture", "static", "mass_kg", "collision")})
    return o


def obstacle_box(name, x, y, yaw) -> dict:
    """A green 0.6 x 0.6 x 0.2 m box resting on the floor (dynamic: a robot can push it)."""
    return _obj(name, "box", (x, y, OBSTACLE_SIZE_M[2] / 2.0), yaw, GREEN, size_m=list(OBSTACLE_SIZE_M),
                static=False, mass_kg=OBSTACLE_MASS_KG)


def obstacles(spec: Sequence[dict], dims: TrackDimensions = NOMINAL) -> List[dict]:
    """Boxes centred on a loop's lane centre, square to the lane."""
    out = []
    radii = lane_radii(dims)
    for i, ob in enumerate(spec):
        x, y, heading = loop_point(ob["loop"], ob["angle_deg"], radii[ob["lane"]], dims)
        out.append(obstacle_box("obstacle_%d" % (i + 1), x, y, heading))
    return out


def box_corners(obj: dict) -> List[Tuple[float, float]]:
    """Footprint corners (x, y) of a box object."""
    (x, y, _), yaw = obj["pose"]["xyz"], obj["pose"]["rpy"][2]
    hx, hy = obj["size_m"][0] / 2.0, obj["size_m"][1] / 2.0
    c, s = math.cos(yaw), math.sin(yaw)
    return [(x + c * u - s * v, y + s * u + c * v) for u, v in ((hx, hy), (-hx, hy), (-hx, -hy), (hx, -hy))]


def cone(name, x, y) -> dict:
    return _obj(name, "cone", (x, y, CONE_HEIGHT_M / 2.0), 0.0, ORANGE, radius_m=CONE_BASE_RADIUS_M,
                length_m=CONE_HEIGHT_M, static=False, mass_kg=CONE_MASS_KG)


def working_zone(spec: dict, dims: TrackDimensions = NOMINAL) -> List[dict]:
    """Cones closing one lane of a loop between from_deg and to_deg: a taper from the closed lane's
    boundary line to the lane divider, cones along the divider, a taper back.  Traffic in the
    closed lane changes to the other lane and back."""
    loop, lane = spec["loop"], spec["lane"]
    side = 1.0 if lane == "outer" else -1.0
    r_divider = dims.loop_radius_m + side * CONE_DIVIDER_CLEARANCE_M
    r_line = outer_line_radius(dims) if lane == "outer" else island_line_radius(dims)
    r_edge = r_line - side * CONE_DIVIDER_CLEARANCE_M
    a0, a1 = spec["from_deg"], spec["to_deg"]
    taper = min(TAPER_DEG, (a1 - a0) / 3.0)
    step_deg = math.degrees(CONE_SPACING_M / r_divider)
    angles, radii = [], []
    for k in range(3):  # taper in: edge -> divider
        f = k / 3.0
        angles.append(a0 + f * taper)
        radii.append(r_edge + f * (r_divider - r_edge))
    n = max(1, int(math.floor((a1 - a0 - 2 * taper) / step_deg)))
    for k in range(n + 1):
        angles.append(a0 + taper + k * (a1 - a0 - 2 * taper) / n)
        radii.append(r_divider)
    for k in range(1, 4):  # taper out: divider -> edge
        f = k / 3.0
        angles.append(a1 - taper + f * taper)
        radii.append(r_divider + f * (r_edge - r_divider))
    out = []
    for i, (a, r) in enumerate(zip(angles, radii)):
        x, y, _ = loop_point(loop, a, r, dims)
        out.append(cone("cone_%d" % (i + 1), x, y))
    return out


def tunnel(spec: dict, dims: TrackDimensions = NOMINAL) -> List[dict]:
    """A roofed section over a loop between from_deg and to_deg: two walls (outside the island
    line and outside the outer line) and a roof, each made of straight boxes, one per
    TUNNEL_SEGMENT_DEG of arc (chords slightly lengthened so that they overlap)."""
    loop, a0, a1 = spec["loop"], spec["from_deg"], spec["to_deg"]
    r_in = island_line_radius(dims) - TUNNEL_MARGIN_M - TUNNEL_WALL_M / 2.0
    r_out = outer_line_radius(dims) + TUNNEL_MARGIN_M + TUNNEL_WALL_M / 2.0
    n = max(1, int(math.ceil((a1 - a0) / TUNNEL_SEGMENT_DEG)))
    d = (a1 - a0) / n
    out = []
    for k in range(n):
        mid = a0 + (k + 0.5) * d
        half = math.radians(d) / 2.0
        for wall, r in (("inner", r_in), ("outer", r_out)):
            # The chord of the wall's circle, lengthened by the wall thickness to close the joints.
            length = 2.0 * r * math.sin(half) + TUNNEL_WALL_M
            x, y, heading = loop_point(loop, mid, r * math.cos(half), dims)
            out.append(_obj("tunnel_wall_%s_%d" % (wall, k + 1), "box", (x, y, TUNNEL_HEIGHT_M / 2.0), heading,
                            TUNNEL_GREY, size_m=[_r(length), TUNNEL_WALL_M, TUNNEL_HEIGHT_M]))
        r_mid = 0.5 * (r_in + r_out)
        length = 2.0 * (r_out + TUNNEL_WALL_M) * math.sin(half) + TUNNEL_WALL_M
        x, y, heading = loop_point(loop, mid, r_mid * math.cos(half), dims)
        out.append(_obj("tunnel_roof_%d" % (k + 1), "box", (x, y, TUNNEL_HEIGHT_M + TUNNEL_ROOF_M / 2.0), heading,
                        TUNNEL_GREY, size_m=[_r(length), _r(r_out - r_in + TUNNEL_WALL_M), TUNNEL_ROOF_M]))
    return out


def tunnel_light_region(spec: dict, dims: TrackDimensions = NOMINAL) -> dict:
    """The world file's light region (docs/world_format.md) of a tunnel: the ground, the walls'
    inner faces and the roof's underside between the walls' centre lines, from the floor up to the
    roof, at TUNNEL_LIGHT."""
    loop, a0, a1 = spec["loop"], spec["from_deg"], spec["to_deg"]
    r_in = island_line_radius(dims) - TUNNEL_MARGIN_M - TUNNEL_WALL_M / 2.0
    r_out = outer_line_radius(dims) + TUNNEL_MARGIN_M + TUNNEL_WALL_M / 2.0
    n = max(1, int(math.ceil((a1 - a0) / TUNNEL_LIGHT_STEP_DEG)))
    angles = [a0 + (a1 - a0) * k / n for k in range(n + 1)]
    outline = ([loop_point(loop, a, r_out, dims)[:2] for a in angles]
               + [loop_point(loop, a, r_in, dims)[:2] for a in reversed(angles)])
    return {"name": "tunnel_%s" % loop, "polygon_xy_m": [[_r(x), _r(y)] for x, y in outline],
            "z_range_m": [-0.01, TUNNEL_HEIGHT_M], "light": TUNNEL_LIGHT}


def parallel_bay(dims: TrackDimensions = NOMINAL) -> Tuple[Tuple[float, float], Tuple[float, float]]:
    """((x_min, x_max), (y_min, y_max)) of the parallel bay's straight part, inside the lines [m]."""
    x0 = dims.x_ref_m + dims.line_spacing_m + dims.solid_width_m / 2.0
    x1 = dims.bulge_line_x_m - dims.bulge_line_width_m / 2.0
    return (x0, x1), dims.bulge_straight_y_m


def parallel_boxes(spec: dict, dims: TrackDimensions = NOMINAL) -> List[dict]:
    """Two boxes in the parallel bay, a gap of gap_m between them centred on the bay."""
    (x0, x1), (y0, y1) = parallel_bay(dims)
    xc, yc = 0.5 * (x0 + x1), 0.5 * (y0 + y1)
    d = spec["gap_m"] / 2.0 + OBSTACLE_SIZE_M[1] / 2.0
    return [obstacle_box("parked_box_south", xc, yc - d, 0.0), obstacle_box("parked_box_north", xc, yc + d, 0.0)]


def bay_box(bay: str, dims: TrackDimensions = NOMINAL) -> List[dict]:
    """A box in the middle of bay 'north' or 'south' of the bay-parking area."""
    (xa, xb), (ya, yb) = parking_bays(dims)[bay]
    return [obstacle_box("parked_box_%s" % bay, 0.5 * (xa + xb), 0.5 * (ya + yb), 0.0)]


def parking_bays(dims: TrackDimensions = NOMINAL) -> Dict[str, tuple]:
    """{bay: ((x_min, x_max), (y_min, y_max))} inside the white lines, as Track.bays [m]."""
    (x0, x1), (y0, y1), b = dims.bay_area_x_m, dims.bay_area_y_m, dims.bay_border_m
    xs = (x0 + b["west"], x1 - b["east"])
    return {"north": (xs, (dims.bay_divider_y_m[1], y1 - b["north"])),
            "south": (xs, (y0 + b["south"], dims.bay_divider_y_m[0]))}


def sign_poses(dims: TrackDimensions = NOMINAL) -> List[Tuple[float, float, float]]:
    """SIGN_POSES carried over to the track dims (the same place relative to the lines near them)."""
    return [dims.map_xy(x, y) + (yaw,) for x, y, yaw in SIGN_POSES]


def sign_object(index: int, sign: str, texture: str, dims: TrackDimensions = NOMINAL) -> dict:
    """Traffic-sign face number `index` (0..11) showing `sign` (its texture file)."""
    x, y, yaw = sign_poses(dims)[index]
    # Roll +90 deg turns the textured +z face to -y and the image top to +z (upright).
    return _obj("sign_%02d_%s" % (index + 1, sign), "box", (x, y, SIGN_CENTRE_HEIGHT_M), color=[0.9, 0.9, 0.9],
                size_m=[SIGN_SIZE_M, SIGN_SIZE_M, SIGN_THICKNESS_M], rpy=(1.5708, 0.0, yaw), texture=texture,
                collision=False)


def sign_order(signs: Sequence[str], seed: int) -> List[str]:
    """The signs over the twelve positions: as listed for seed 0, shuffled by any other seed."""
    order = list(signs)
    if seed:
        random.Random(seed).shuffle(order)
    return order


def random_obstacles(seed: int, angle_range_deg, keep_clear: Sequence[dict] = ()) -> List[dict]:
    """One box per loop at a random angle and lane (the other lane stays free), drawn with
    random.Random(seed), away from the arcs in keep_clear ({loop, from_deg, to_deg}).  Raises
    ChallengeError naming the seed when no position is found."""
    rng = random.Random(seed)
    lo, hi = angle_range_deg
    out = []
    for loop in ("north", "south"):
        for _ in range(RANDOM_ATTEMPTS):
            angle = rng.uniform(lo, hi)
            if all(z["loop"] != loop or not (z["from_deg"] - RANDOM_CLEARANCE_DEG <= angle
                                             <= z["to_deg"] + RANDOM_CLEARANCE_DEG) for z in keep_clear):
                break
        else:
            raise ChallengeError("seed %d: cannot place the obstacle of the %s loop in %g..%g deg away from the "
                                 "working zone and the tunnel (%d attempts)" % (seed, loop, lo, hi, RANDOM_ATTEMPTS))
        out.append({"loop": loop, "lane": rng.choice(("inner", "outer")), "angle_deg": round(angle, 2)})
    return out
