"""The open-loop walk of the NAO, free of ROS: footsteps -> ZMP reference -> CoM from the preview
controller -> swing feet -> leg angles by analytic IK, sampled at the control period.

Timeline: `start_s` standing (the CoM settles midway between the feet), then per footstep a
double support (ZMP moves to the support foot) and a single support (ZMP on the support foot, the
other foot swings to its footstep), then a double support back to midway and `end_s` standing.
The torso stays upright at a constant height; its yaw is the mean of the feet's yaws.
"""

import math
from dataclasses import dataclass

import numpy as np

from conde_humanoid import leg_ik
from conde_humanoid.footsteps import Footstep
from conde_humanoid.preview_control import PreviewController
from conde_humanoid.swing import blend, swing_pose


@dataclass(frozen=True)
class GaitParameters:
    """Conservative NAO gait: short, slow steps, knees well bent."""
    control_period_s: float = 0.01
    step_period_s: float = 0.5           # one step, double support included
    double_support_s: float = 0.15
    max_step_length_m: float = 0.04      # -> max forward speed 0.08 m/s
    max_step_turn_rad: float = 0.2       # -> max turn rate 0.4 rad/s
    foot_separation_m: float = 0.1       # ankle to ankle, = the hips' spacing
    step_height_m: float = 0.02
    torso_height_m: float = 0.30         # torso origin above the ground
    com_height_m: float = 0.28           # of the cart-table model
    com_offset_x_m: float = 0.0          # whole-body CoM ahead of the torso origin
    zmp_offset_x_m: float = 0.01         # ZMP reference ahead of the ankle
    start_s: float = 0.6
    end_s: float = 0.8
    preview_s: float = 1.6

    @property
    def max_speed_m_s(self):
        return self.max_step_length_m / self.step_period_s

    @property
    def max_turn_rate_rad_s(self):
        return self.max_step_turn_rad / self.step_period_s


@dataclass
class WalkPattern:
    time_s: np.ndarray       # from the start of the walk
    joints: dict             # {joint name: np.ndarray of angles [rad]}, the 12 leg joints
    com_m: np.ndarray        # (n, 2) planned CoM x, y
    zmp_ref_m: np.ndarray    # (n, 2)
    zmp_m: np.ndarray        # (n, 2) ZMP of the planned CoM (cart-table model)
    feet_end: tuple          # final (L, R) Footsteps


def _zmp_point(foot, params):
    c, s = math.cos(foot.yaw_rad), math.sin(foot.yaw_rad)
    return np.array([foot.x_m + c * params.zmp_offset_x_m, foot.y_m + s * params.zmp_offset_x_m])


def _mid(left, right, params):
    return 0.5 * (_zmp_point(left, params) + _zmp_point(right, params))


def generate(feet_start, footsteps, params=GaitParameters(), controller=None):
    """The walk from the standing feet `feet_start` (L, R Footsteps) over `footsteps`."""
    dt = params.control_period_s
    n_start = int(round(params.start_s / dt))
    n_ds = int(round(params.double_support_s / dt))
    n_ss = int(round((params.step_period_s - params.double_support_s) / dt))
    n_end = int(round(params.end_s / dt))
    feet = {'L': feet_start[0], 'R': feet_start[1]}
    # Per tick: ZMP reference, and the feet as (x, y, z, yaw) each.
    zmp_ref, left, right = [], [], []

    def emit(zmp, poses):
        zmp_ref.append(zmp)
        left.append(poses['L'])
        right.append(poses['R'])

    def flat(foot):
        return (foot.x_m, foot.y_m, 0.0, foot.yaw_rad)

    here = _mid(feet['L'], feet['R'], params)
    for _ in range(n_start):
        emit(here, {k: flat(f) for k, f in feet.items()})
    for step in footsteps:
        if step.side not in feet:
            raise ValueError('footstep side must be L or R: %r' % (step,))
        support = feet['R' if step.side == 'L' else 'L']
        target = _zmp_point(support, params)
        for i in range(n_ds):
            s = (i + 1) / n_ds
            emit(here + (target - here) * s, {k: flat(f) for k, f in feet.items()})
        here = target
        start = (feet[step.side].x_m, feet[step.side].y_m, feet[step.side].yaw_rad)
        end = (step.x_m, step.y_m, step.yaw_rad)
        for i in range(n_ss):
            poses = {k: flat(f) for k, f in feet.items()}
            poses[step.side] = swing_pose(start, end, params.step_height_m, (i + 1) / n_ss)
            emit(here, poses)
        feet[step.side] = Footstep(step.side, step.x_m, step.y_m, step.yaw_rad)
    target = _mid(feet['L'], feet['R'], params)
    for i in range(n_ds):
        emit(here + (target - here) * ((i + 1) / n_ds), {k: flat(f) for k, f in feet.items()})
    for _ in range(n_end):
        emit(target, {k: flat(f) for k, f in feet.items()})

    zmp_ref = np.array(zmp_ref)
    if controller is None:
        controller = PreviewController(params.com_height_m, dt, params.preview_s)
    com_x, zmp_x = controller.run(zmp_ref[:, 0])
    com_y, zmp_y = controller.run(zmp_ref[:, 1])
    left, right = np.array(left), np.array(right)
    joints = {}
    for k in range(len(zmp_ref)):
        yaw = 0.5 * (left[k, 3] + right[k, 3])
        c, s = math.cos(yaw), math.sin(yaw)
        torso = np.array([com_x[k] - c * params.com_offset_x_m, com_y[k] - s * params.com_offset_x_m,
                          params.torso_height_m])
        rel = []
        for foot in (left[k], right[k]):
            d = np.array([foot[0], foot[1], foot[2] + leg_ik.FOOT_HEIGHT_M]) - torso
            rel.append((np.array([c * d[0] + s * d[1], -s * d[0] + c * d[1], d[2]]), foot[3] - yaw))
        angles = leg_ik.inverse_pair(rel[0][0], rel[0][1], rel[1][0], rel[1][1])
        for name, angle in angles.items():
            joints.setdefault(name, []).append(angle)
    return WalkPattern(time_s=dt * np.arange(len(zmp_ref)),
                       joints={name: np.array(v) for name, v in joints.items()},
                       com_m=np.column_stack([com_x, com_y]), zmp_ref_m=zmp_ref,
                       zmp_m=np.column_stack([zmp_x, zmp_y]), feet_end=(feet['L'], feet['R']))


def blend_phase(s):
    """Exposed for tests: the swing blend."""
    return blend(s)
