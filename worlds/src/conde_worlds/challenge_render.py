"""Top view of a challenge world: the floor texture with the objects' footprints in their colours.

Pure numpy + OpenCV, no ROS.  For documentation and quick checks, not for cameras.
"""

import math
import os

import cv2
import numpy as np
import yaml

from .challenges import default_path
from .track_render import world_to_pixel

TOP_VIEW_PX_PER_M = 40.0
#: Objects drawn half transparent, so that what is under them shows.
SEE_THROUGH = ("tunnel_roof_",)


def _rotation(rpy):
    r, p, y = rpy
    cr, sr, cp, sp, cy, sy = math.cos(r), math.sin(r), math.cos(p), math.sin(p), math.cos(y), math.sin(y)
    return np.array([[cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr],
                     [sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr],
                     [-sp, cp * sr, cp * cr]])


def footprint(obj: dict) -> np.ndarray:
    """(N, 2) world x, y outline of an object seen from above (convex hull of a box's corners,
    a polygon around a cylinder, cone or sphere)."""
    xyz = np.array(obj["pose"]["xyz"], float)
    rpy = obj["pose"].get("rpy", [0.0, 0.0, 0.0])
    if obj["shape"] == "box":
        h = np.array(obj["size_m"], float) / 2.0
        corners = np.array([[sx, sy, sz] for sx in (-1, 1) for sy in (-1, 1) for sz in (-1, 1)]) * h
        pts = corners @ _rotation(rpy).T + xyz
        hull = cv2.convexHull(pts[:, :2].astype(np.float32)).reshape(-1, 2)
        return hull.astype(float)
    a = np.linspace(0.0, 2.0 * math.pi, 24, endpoint=False)
    r = obj["radius_m"]
    return np.stack([xyz[0] + r * np.cos(a), xyz[1] + r * np.sin(a)], axis=1)


def render_top_view(world: dict, floor_rgb: np.ndarray, x_range, y_range,
                    resolution: float = TOP_VIEW_PX_PER_M) -> np.ndarray:
    """RGB top view at `resolution` px/m of the floor image (covering x_range, y_range) and the
    world's objects; roofs (SEE_THROUGH) are drawn half transparent."""
    w = int(round((x_range[1] - x_range[0]) * resolution))
    h = int(round((y_range[1] - y_range[0]) * resolution))
    img = cv2.resize(floor_rgb, (w, h), interpolation=cv2.INTER_AREA).astype(np.float32)
    for obj in world.get("objects") or []:
        colour = np.array(obj.get("color_rgb", [0.7, 0.7, 0.7]), np.float32) * 255.0
        col, row = world_to_pixel(*footprint(obj).T, resolution, x_range, y_range)
        poly = np.round(np.stack([col, row], axis=1) * 4).astype(np.int32)
        layer = img.copy()
        cv2.fillPoly(layer, [poly], colour.tolist(), cv2.LINE_AA, shift=2)
        alpha = 0.35 if obj["name"].startswith(SEE_THROUGH) else 1.0
        img = alpha * layer + (1.0 - alpha) * img
    return np.clip(img, 0, 255).astype(np.uint8)


def write_top_view(world_path: str, png_path: str, resolution: float = TOP_VIEW_PX_PER_M):
    """Draws the world file `world_path` from above into `png_path` (its ground texture must be a
    package://conde_worlds/ or relative path)."""
    with open(world_path) as f:
        world = yaml.safe_load(f)
    ground = world["ground"]
    texture = ground["texture"]
    if texture.startswith("package://conde_worlds/"):
        package_dir = os.path.dirname(os.path.dirname(default_path()))  # beside challenges/
        texture = os.path.join(package_dir, texture[len("package://conde_worlds/"):])
    elif not os.path.isabs(texture):
        texture = os.path.join(os.path.dirname(world_path), texture)
    floor = cv2.imread(texture)
    if floor is None:
        raise IOError("cannot read the ground texture %s" % texture)
    img = render_top_view(world, cv2.cvtColor(floor, cv2.COLOR_BGR2RGB), ground["x_range_m"], ground["y_range_m"],
                          resolution)
    if not cv2.imwrite(png_path, cv2.cvtColor(img, cv2.COLOR_RGB2BGR), [cv2.IMWRITE_PNG_COMPRESSION, 9]):
        raise IOError("cannot write %s" % png_path)
