"""What nao_walk plans for a request, free of ROS: where the robot's feet are (open loop: where
the last walk put them), a walk-to request (distance or angle at a fraction of the maximum
speed) or a velocity command for a burst of steps -> footsteps -> joint pattern."""

import math

from conde_humanoid import footsteps as fs
from conde_humanoid.walk_pattern import GaitParameters, generate


class WalkRequestError(ValueError):
    """A request nao_walk refuses; the message says why."""


class WalkPlanner:
    def __init__(self, params=GaitParameters()):
        self.params = params
        self.body = fs.Pose2D()  # planned body pose in the frame the robot started in

    def ready_pattern(self):
        """Standing still in the walking posture (the first sample of any walk)."""
        return generate(self._feet(), [], self.params)

    def _feet(self):
        return fs.standing_feet(self.body, self.params.foot_separation_m)

    def plan_walk_to(self, distance_m, angle_rad, speed_fraction):
        values = (distance_m, angle_rad, speed_fraction)
        if not all(math.isfinite(v) for v in values):
            raise WalkRequestError('distance_m, angle_rad and speed_fraction must be finite, got %r' % (values,))
        if not 0 < speed_fraction <= 1:
            raise WalkRequestError('speed_fraction must be in (0, 1], got %g' % speed_fraction)
        if (distance_m != 0) == (angle_rad != 0):
            raise WalkRequestError('give exactly one of distance_m and angle_rad non-zero, got %g m and %g rad'
                                   % (distance_m, angle_rad))
        p = self.params
        if distance_m:
            steps = fs.plan_straight(distance_m, speed_fraction * p.max_step_length_m, p.foot_separation_m, self.body)
        else:
            steps = fs.plan_turn(angle_rad, speed_fraction * p.max_step_turn_rad, p.foot_separation_m, self.body)
        return self._walk(steps)

    def plan_velocity(self, vx_m_s, vy_m_s, wz_rad_s, steps=4):
        """`steps` steps at a velocity (clamped to the gait's maximum), then standing."""
        p = self.params
        t = p.step_period_s
        dx = max(-p.max_step_length_m, min(p.max_step_length_m, vx_m_s * t))
        dy = max(-p.max_step_length_m / 2, min(p.max_step_length_m / 2, vy_m_s * t))
        dyaw = max(-p.max_step_turn_rad, min(p.max_step_turn_rad, wz_rad_s * t))
        first = 'L' if (dy > 0 or (dy == 0 and dyaw > 0)) else 'R'
        return self._walk(fs.plan_from_increments(self.body, [(dx, dy, dyaw)] * steps, first, p.foot_separation_m))

    def _walk(self, steps):
        pattern = generate(self._feet(), steps, self.params)
        left, right = pattern.feet_end
        self.body = fs.Pose2D(0.5 * (left.x_m + right.x_m), 0.5 * (left.y_m + right.y_m),
                              0.5 * (left.yaw_rad + right.yaw_rad))
        return pattern
