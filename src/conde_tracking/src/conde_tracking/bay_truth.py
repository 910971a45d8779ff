"""Ground truth of the bay-parking area in the rendered views (test/data/b2v1_*.npz and b2v2_*.npz,
rendered by scripts/render_test_images in the B2 worlds on the nominal track): its lines across
the road, located like conde_tracking.parking_area reports them (x ahead of base_footprint where
each meets the road side), and which bay holds the box.  Used by test_parking_area.py and
scripts/parking_area_accuracy; needs conde_worlds (the track geometry)."""
import math
import os
from typing import Dict, List

import numpy as np

from conde_worlds.track_geometry import build_track

VIEWS = ["b2%s_%s" % (v, name) for v in ("v1", "v2") for name in (
    "bays_ahead_1m", "bays_ahead_0_5m", "south_bay_beside", "north_bay_ahead", "bays_heading_right_8deg",
    "bays_heading_left_8deg")]
#: the bay that holds the box in each rendered variant of B2
OCCUPIED = {"v1": "north", "v2": "south"}


def world_bay_lines() -> Dict[str, np.ndarray]:
    """The lines across the bay-parking area (south border, divider, north border): (x, y) [m] in
    the world of their centre line's end at the road side."""
    track = build_track()
    (x0, _), _ = track.dims.bay_area_x_m, track.dims.bay_area_y_m
    (_, (y_south, y_div0)), ((_, (y_div1, y_north))) = track.bays["south"], track.bays["north"]
    b = track.dims.bay_border_m
    return {"south_border": np.array([x0, y_south - 0.5 * b["south"]]),
            "divider": np.array([x0, 0.5 * (y_div0 + y_div1)]),
            "north_border": np.array([x0, y_north + 0.5 * b["north"]])}


def lines_in_robot_frame(pose_xy_yaw) -> Dict[str, float]:
    """x [m] ahead of base_footprint of each line's road-side end, for the robot at pose (x, y, yaw)."""
    x0, y0, yaw = (float(v) for v in pose_xy_yaw)
    c, s = math.cos(yaw), math.sin(yaw)
    return {name: float(c * (p[0] - x0) + s * (p[1] - y0)) for name, p in world_bay_lines().items()}


def occupied_bay(view: str) -> str:
    """The bay holding the box in a rendered view (by its name's variant)."""
    return OCCUPIED[view[2:4]]


def load_views(data_dir: str) -> List[tuple]:
    """(name, npz data) of every rendered view; a missing file is an error naming it."""
    out = []
    for name in VIEWS:
        path = os.path.join(data_dir, name + ".npz")
        if not os.path.exists(path):
            raise FileNotFoundError("%s: missing (render it with render_test_images)" % path)
        out.append((name, np.load(path)))
    return out
