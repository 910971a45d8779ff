"""Footstep plans for the open-loop walk, free of ROS.

A plan is the list of footsteps (side, ankle x, y [m], yaw [rad] in the frame the walk starts in:
x forward, y left, origin midway between the ankles). The body (midway between the feet, its yaw
the mean of theirs) advances one increment (dx, dy [m], dyaw [rad], in its own frame) per step;
the swinging foot lands beside it; a last step brings the other foot alongside. The feet are yawed
symmetrically about the body, as NAO's coupled HipYawPitch joints require.
"""

import math
from dataclasses import dataclass


@dataclass(frozen=True)
class Footstep:
    side: str         # 'L' | 'R'
    x_m: float
    y_m: float
    yaw_rad: float


@dataclass(frozen=True)
class Pose2D:
    x_m: float = 0.0
    y_m: float = 0.0
    yaw_rad: float = 0.0

    def compose(self, dx_m, dy_m, dyaw_rad):
        """This pose moved by an increment given in its own frame."""
        c, s = math.cos(self.yaw_rad), math.sin(self.yaw_rad)
        return Pose2D(self.x_m + c * dx_m - s * dy_m, self.y_m + s * dx_m + c * dy_m, self.yaw_rad + dyaw_rad)


def foot_beside(body, side, foot_separation_m):
    half = foot_separation_m / 2 if side == 'L' else -foot_separation_m / 2
    p = body.compose(0.0, half, 0.0)
    return Footstep(side, p.x_m, p.y_m, body.yaw_rad)


def standing_feet(body, foot_separation_m):
    """The two feet (L, R) of a robot standing at `body`."""
    return foot_beside(body, 'L', foot_separation_m), foot_beside(body, 'R', foot_separation_m)


def plan_from_increments(start, increments, first_side, foot_separation_m):
    """Footsteps that move the body from `start` (Pose2D) by each (dx, dy, dyaw) of `increments`,
    the `first_side` foot first, then one step bringing the trailing foot alongside."""
    if first_side not in ('L', 'R'):
        raise ValueError("first_side must be 'L' or 'R'")
    steps = []
    body, side = start, first_side
    for dx, dy, dyaw in increments:
        body = body.compose(dx, dy, dyaw)
        steps.append(foot_beside(body, side, foot_separation_m))
        side = 'R' if side == 'L' else 'L'
    if increments:
        steps.append(foot_beside(body, side, foot_separation_m))
    return steps


def _count(amount, per_step):
    return max(1, math.ceil(abs(amount) / per_step - 1e-9)) if amount != 0 else 0


def plan_straight(distance_m, step_length_m, foot_separation_m, start=Pose2D()):
    """Steps of at most `step_length_m` covering `distance_m` (negative: backwards), all equal."""
    if step_length_m <= 0:
        raise ValueError('step_length_m must be > 0')
    n = _count(distance_m, step_length_m)
    return plan_from_increments(start, [(distance_m / n, 0.0, 0.0)] * n, 'R', foot_separation_m) if n else []


def plan_turn(angle_rad, step_turn_rad, foot_separation_m, start=Pose2D()):
    """Steps turning on the spot by `angle_rad` (positive: counter-clockwise) at most
    `step_turn_rad` per step; the foot on the side of the turn opens first."""
    if step_turn_rad <= 0:
        raise ValueError('step_turn_rad must be > 0')
    n = _count(angle_rad, step_turn_rad)
    first = 'L' if angle_rad > 0 else 'R'
    return plan_from_increments(start, [(0.0, 0.0, angle_rad / n)] * n, first, foot_separation_m) if n else []
