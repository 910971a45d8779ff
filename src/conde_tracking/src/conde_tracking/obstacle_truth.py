"""Ground truth of the boxes and cones in the rendered obstacle views (test/data/d4_*.npz, rendered
by scripts/render_test_images in the D4 v1 world): each object's footprint in base_footprint and
its near edge and lateral extent on the floor.  Used by test_obstacles.py and
scripts/obstacle_accuracy; needs conde_worlds (the challenge layouts)."""
import math
from dataclasses import dataclass
from typing import List

import numpy as np

from conde_worlds import challenge_objects as co
from conde_worlds.challenge_world import layout, objects_of
from conde_worlds.challenges import load_challenges

RENDERED_CHALLENGE = ("D4", "v1")
VIEWS = ["d4_box_ahead_1m", "d4_box_ahead_1_5m", "d4_box_beside", "d4_box_other_lane", "d4_cones_ahead",
         "d4_cones_beside"]


@dataclass(frozen=True)
class TrueObject:
    name: str
    kind: str  # "box" or "cone"
    near_x_m: float
    y_min_m: float  # lateral extent of the footprint
    y_max_m: float
    footprint_xy_m: np.ndarray  # (N, 2) points of the footprint in base_footprint


def world_objects(challenge=RENDERED_CHALLENGE):
    """(name, kind, footprint points (N, 2) in the world) of the boxes and cones of a challenge."""
    features = layout(load_challenges(), challenge[0], challenge[1], 0)[3]
    out = []
    for ob in objects_of(features, 0)[0]:
        if ob["name"].startswith("obstacle_"):
            corners = np.array(co.box_corners(ob))
            u, v = np.meshgrid(np.linspace(0, 1, 25), np.linspace(0, 1, 25))
            a, b, d = corners[0], corners[1], corners[3]
            pts = a + u.reshape(-1, 1) * (b - a) + v.reshape(-1, 1) * (d - a)
            out.append((ob["name"], "box", pts))
        elif ob["name"].startswith("cone_"):
            x, y = ob["pose"]["xyz"][:2]
            r = ob["radius_m"]
            rho, phi = np.meshgrid(np.linspace(0, r, 8), np.linspace(0, 2 * math.pi, 36))
            pts = np.column_stack([x + (rho * np.cos(phi)).ravel(), y + (rho * np.sin(phi)).ravel()])
            out.append((ob["name"], "cone", pts))
    return out


def objects_in_robot_frame(pose_xy_yaw, challenge=RENDERED_CHALLENGE) -> List[TrueObject]:
    x0, y0, yaw = (float(v) for v in pose_xy_yaw)
    c, s = math.cos(yaw), math.sin(yaw)
    out = []
    for name, kind, pts in world_objects(challenge):
        dx, dy = pts[:, 0] - x0, pts[:, 1] - y0
        local = np.column_stack([c * dx + s * dy, -s * dx + c * dy])
        out.append(TrueObject(name, kind, float(local[:, 0].min()), float(local[:, 1].min()), float(local[:, 1].max()),
                              local))
    return out
