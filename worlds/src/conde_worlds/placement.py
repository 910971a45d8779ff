"""Placement seeds: the robot put down a little differently in its start area, as a team member
would, for the robustness benchmark (conde_tournament robustness).

Pure Python, no ROS.  Placement seed 0 is the challenge's nominal start pose; a seed N > 0 moves
it by an offset drawn with random.Random("placement-N") uniformly within the start area of challenges.yaml
(`placement`): along the start heading (`along_m`, backwards only, so the robot is never put
nearer the crosswalk than the nominal pose), across it (`across_m`) and in heading (`yaw_deg`).
The offset is the same for every robot and track (a varied track's start pose is carried over
first, then the offset is applied in that pose's frame), so one seed means one placement.
"""

import math
import random
from dataclasses import dataclass
from typing import Dict, Tuple

#: Hard bounds of the start area [m, m, deg]: a placement never reaches the crosswalk (ahead) nor
#: the referee's start line (0.21 m behind the crosswalk start) and stays well inside the 0.746 m
#: lane.
AREA_LIMITS = {"along_m": (-0.15, 0.0), "across_m": (-0.08, 0.08), "yaw_deg": (-8.0, 8.0)}


@dataclass(frozen=True)
class StartArea:
    """Where a robot may be put, relative to the nominal start pose: ranges [lo, hi] along the
    start heading [m], across it (left positive) [m] and in heading (counter-clockwise) [deg]."""
    along_m: Tuple[float, float] = (0.0, 0.0)
    across_m: Tuple[float, float] = (0.0, 0.0)
    yaw_deg: Tuple[float, float] = (0.0, 0.0)

    def contains(self, offset: "Offset") -> bool:
        return all(lo <= value <= hi for value, (lo, hi) in ((offset.along_m, self.along_m),
                                                             (offset.across_m, self.across_m),
                                                             (offset.yaw_deg, self.yaw_deg)))


@dataclass(frozen=True)
class Offset:
    """A placement's offset from the nominal start pose (StartArea's axes)."""
    along_m: float = 0.0
    across_m: float = 0.0
    yaw_deg: float = 0.0

    def summary(self) -> dict:
        return {"along_m": self.along_m, "across_m": self.across_m, "yaw_deg": self.yaw_deg}


NOMINAL_AREA = StartArea()


def offset(placement_seed: int, area: StartArea) -> Offset:
    """The offset of a placement seed (0: none), rounded to 0.1 mm and 0.01 deg; always inside
    `area` (ValueError otherwise: a bug, never a quiet pose outside the start area)."""
    if placement_seed == 0:
        return Offset()
    rnd = random.Random("placement-%d" % placement_seed)
    drawn = Offset(round(rnd.uniform(*area.along_m), 4), round(rnd.uniform(*area.across_m), 4),
                   round(rnd.uniform(*area.yaw_deg), 2))
    if not area.contains(drawn):
        # rounding at a bound: clamp into the area
        drawn = Offset(*(min(max(v, lo), hi) for v, (lo, hi) in
                         ((drawn.along_m, area.along_m), (drawn.across_m, area.across_m),
                          (drawn.yaw_deg, area.yaw_deg))))
    if not area.contains(drawn):
        raise ValueError("placement seed %d: offset %s outside the start area %s" % (placement_seed, drawn, area))
    return drawn


def placed(pose: dict, off: Offset) -> dict:
    """The pose {xyz: [x, y, z] m, yaw: rad} moved by `off` in its own frame."""
    x, y = pose["xyz"][0], pose["xyz"][1]
    yaw = pose["yaw"]
    c, s = math.cos(yaw), math.sin(yaw)
    return {"xyz": [round(x + off.along_m * c - off.across_m * s, 4), round(y + off.along_m * s + off.across_m * c, 4)]
            + list(pose["xyz"][2:]),
            "yaw": round(yaw + math.radians(off.yaw_deg), 5)}


def offset_of(nominal: dict, pose: dict) -> Offset:
    """The offset of `pose` from `nominal` in the nominal pose's frame (the inverse of placed)."""
    dx, dy = pose["xyz"][0] - nominal["xyz"][0], pose["xyz"][1] - nominal["xyz"][1]
    c, s = math.cos(nominal["yaw"]), math.sin(nominal["yaw"])
    return Offset(dx * c + dy * s, -dx * s + dy * c, math.degrees(pose["yaw"] - nominal["yaw"]))


def placed_poses(poses: Dict[str, dict], placement_seed: int, area: StartArea) -> Dict[str, dict]:
    """{robot: pose} of a start with the placement seed applied (seed 0: the poses unchanged)."""
    if placement_seed == 0:
        return poses
    off = offset(placement_seed, area)
    return {robot: placed(pose, off) for robot, pose in poses.items()}
