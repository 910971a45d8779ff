"""The robot's footprint: the axis-aligned rectangle, in the root link's frame, that holds every
collision shape of its URDF (boxes, cylinders and spheres by their bounding boxes; meshes are not
read), with all joints at zero. Pure Python (xml.etree, numpy), no ROS.

The ground-truth pose (/ground_truth/odom) is the root link's (base_footprint for Conde), so the
footprint in the world is this rectangle moved by that pose."""
import functools
import math
import xml.etree.ElementTree as ET
from dataclasses import dataclass
from typing import List, Tuple

import numpy as np


class FootprintError(ValueError):
    """A robot description the referee cannot use; the message says why."""


@dataclass(frozen=True)
class Footprint:
    x_min_m: float
    x_max_m: float
    y_min_m: float
    y_max_m: float
    z_max_m: float = 1.0  # top of the highest collision shape [m above the root link]

    def corners(self, x_m, y_m, yaw_rad) -> np.ndarray:
        """(4, 2) world corners for the root link at (x_m, y_m, yaw_rad), counter-clockwise."""
        local = np.array([[self.x_max_m, self.y_max_m], [self.x_min_m, self.y_max_m],
                          [self.x_min_m, self.y_min_m], [self.x_max_m, self.y_min_m]])
        return _place(local, x_m, y_m, yaw_rad)

    def samples(self, x_m, y_m, yaw_rad, spacing_m=0.02) -> np.ndarray:
        """(N, 2) world points on a grid over the rectangle, at most spacing_m apart, edges included."""
        return _place(self._grid(spacing_m), x_m, y_m, yaw_rad)

    @functools.lru_cache(maxsize=8)
    def _grid(self, spacing_m) -> np.ndarray:
        """The (N, 2) grid of samples() in the root link's frame (read-only: it is shared)."""
        nx = max(2, int(math.ceil((self.x_max_m - self.x_min_m) / spacing_m)) + 1)
        ny = max(2, int(math.ceil((self.y_max_m - self.y_min_m) / spacing_m)) + 1)
        gx, gy = np.meshgrid(np.linspace(self.x_min_m, self.x_max_m, nx), np.linspace(self.y_min_m, self.y_max_m, ny))
        grid = np.column_stack([gx.ravel(), gy.ravel()])
        grid.flags.writeable = False
        return grid


def _place(local, x_m, y_m, yaw_rad):
    c, s = math.cos(yaw_rad), math.sin(yaw_rad)
    return np.column_stack([x_m + c * local[:, 0] - s * local[:, 1], y_m + s * local[:, 0] + c * local[:, 1]])


def _transform(origin) -> np.ndarray:
    """4x4 matrix of a URDF <origin xyz rpy> (None = identity)."""
    xyz = [float(v) for v in (origin.get("xyz", "0 0 0") if origin is not None else "0 0 0").split()]
    r, p, y = [float(v) for v in (origin.get("rpy", "0 0 0") if origin is not None else "0 0 0").split()]
    cr, sr, cp, sp, cy, sy = math.cos(r), math.sin(r), math.cos(p), math.sin(p), math.cos(y), math.sin(y)
    m = np.eye(4)
    m[:3, :3] = [[cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr],
                 [sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr],
                 [-sp, cp * sr, cp * cr]]
    m[:3, 3] = xyz
    return m


def _half_extents(geometry) -> Tuple[float, float, float]:
    box, cyl, sphere = geometry.find("box"), geometry.find("cylinder"), geometry.find("sphere")
    if box is not None:
        return tuple(float(v) / 2.0 for v in box.get("size").split())
    if cyl is not None:
        r = float(cyl.get("radius"))
        return r, r, float(cyl.get("length")) / 2.0
    if sphere is not None:
        r = float(sphere.get("radius"))
        return r, r, r
    return None


def footprint_from_urdf(urdf_xml: str) -> Footprint:
    """The footprint of a URDF robot; raises FootprintError."""
    try:
        robot = ET.fromstring(urdf_xml)
    except ET.ParseError as e:
        raise FootprintError("robot_description: not valid XML: %s" % e)
    name = robot.get("name", "")
    parent_of = {}
    origin_of = {}
    for joint in robot.findall("joint"):
        child = joint.find("child").get("link")
        parent_of[child] = joint.find("parent").get("link")
        origin_of[child] = _transform(joint.find("origin"))

    def pose(link):  # root -> link at zero joint positions
        m = np.eye(4)
        while link in parent_of:
            m = origin_of[link] @ m
            link = parent_of[link]
        return m

    points: List[np.ndarray] = []
    for link in robot.findall("link"):
        for collision in link.findall("collision"):
            geometry = collision.find("geometry")
            half = _half_extents(geometry) if geometry is not None else None
            if half is None:
                continue
            hx, hy, hz = half
            corners = np.array([[sx * hx, sy * hy, sz * hz, 1.0] for sx in (-1, 1) for sy in (-1, 1) for sz in (-1, 1)])
            m = pose(link.get("name")) @ _transform(collision.find("origin"))
            points.append((m @ corners.T).T[:, :3])
    if not points:
        raise FootprintError("robot_description: robot '%s' has no collision geometry (a <collision> with a box, "
                             "cylinder or sphere): the referee needs it for the robot's footprint" % name)
    p = np.vstack(points)
    return Footprint(float(p[:, 0].min()), float(p[:, 0].max()), float(p[:, 1].min()), float(p[:, 1].max()),
                     float(p[:, 2].max()))
