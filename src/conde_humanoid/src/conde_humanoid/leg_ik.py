"""Analytic inverse kinematics of a NAO leg, free of ROS.

Geometry (urdf/robots/nao.urdf.xacro, the manufacturer's numbers) in the torso frame (x forward,
y left, z up): the hip is HIP_OFFSET_Y_M sideways and HIP_OFFSET_Z_M below the torso origin;
HipYawPitch turns about an axis tilted 45 deg in the y-z plane ((0, 1, -1)/sqrt 2 on the left,
(0, 1, 1)/sqrt 2 on the right), then HipRoll (x), HipPitch, KneePitch, AnklePitch (y) and
AnkleRoll (x); thigh THIGH_LENGTH_M, tibia TIBIA_LENGTH_M; the ankle-roll axis is FOOT_HEIGHT_M
above the sole.

Targets are the ankle point (on the ankle-roll axis) and the foot's yaw relative to the torso, with
the sole parallel to the torso's x-y plane. Below the hip the solution is closed form (roll from
the ankle's direction, knee from the leg length, hip and ankle pitch from the triangle, ankle
roll/pitch undoing the rest). HipYawPitch is the one joint whose angle for a given foot yaw has
no simple closed form because its axis is tilted: it is the root of one scalar equation (the part
of the remaining rotation that the roll-pitch-roll chain below cannot make), found by bisection.
"""

import math

import numpy as np

HIP_OFFSET_Y_M = 0.05
HIP_OFFSET_Z_M = -0.085
THIGH_LENGTH_M = 0.1
TIBIA_LENGTH_M = 0.1029
FOOT_HEIGHT_M = 0.04519
LEG_JOINTS = ('HipYawPitch', 'HipRoll', 'HipPitch', 'KneePitch', 'AnklePitch', 'AnkleRoll')
# HipYawPitch range [rad] (both sides); the root is searched in it.
HIP_YAW_PITCH_RANGE_RAD = (-1.14529, 0.740718)


class IkError(ValueError):
    """A target the leg cannot reach."""


def side_sign(side):
    if side not in ('L', 'R'):
        raise ValueError("side must be 'L' or 'R', got %r" % (side,))
    return 1.0 if side == 'L' else -1.0


def rot_x(a):
    c, s = math.cos(a), math.sin(a)
    return np.array([[1, 0, 0], [0, c, -s], [0, s, c]])


def rot_y(a):
    c, s = math.cos(a), math.sin(a)
    return np.array([[c, 0, s], [0, 1, 0], [-s, 0, c]])


def rot_z(a):
    c, s = math.cos(a), math.sin(a)
    return np.array([[c, -s, 0], [s, c, 0], [0, 0, 1]])


def rot_axis(axis, a):
    """Rotation by `a` [rad] about the unit vector `axis` (Rodrigues)."""
    k = np.asarray(axis, dtype=float)
    kx = np.array([[0, -k[2], k[1]], [k[2], 0, -k[0]], [-k[1], k[0], 0]])
    return np.eye(3) + math.sin(a) * kx + (1 - math.cos(a)) * kx @ kx


def hip_yaw_pitch_axis(side):
    s = side_sign(side)
    return np.array([0.0, 1.0, -s]) / math.sqrt(2.0)


def hip_position(side):
    return np.array([0.0, side_sign(side) * HIP_OFFSET_Y_M, HIP_OFFSET_Z_M])


def forward(side, q):
    """Ankle point [m] and foot rotation (3x3) in the torso frame for the six leg angles `q` [rad]
    in LEG_JOINTS order."""
    q0, q1, q2, q3, q4, q5 = q
    r = rot_axis(hip_yaw_pitch_axis(side), q0) @ rot_x(q1) @ rot_y(q2)
    p = hip_position(side) + r @ np.array([0, 0, -THIGH_LENGTH_M])
    r = r @ rot_y(q3)
    p = p + r @ np.array([0, 0, -TIBIA_LENGTH_M])
    r = r @ rot_y(q4) @ rot_x(q5)
    return p, r


def _below_hip(side, ankle_m, foot_rotation, q0):
    """(q1..q5, residual) for a given HipYawPitch q0; residual [-] is the part of the foot rotation
    the roll-pitch-roll chain cannot make (0 when q0 is right)."""
    r0 = rot_axis(hip_yaw_pitch_axis(side), q0)
    p = r0.T @ (np.asarray(ankle_m, dtype=float) - hip_position(side))
    q1 = math.atan2(p[1], -p[2])
    reach_m = math.hypot(p[1], p[2])
    d2 = p[0] ** 2 + reach_m ** 2
    l1, l2 = THIGH_LENGTH_M, TIBIA_LENGTH_M
    cos_knee = (d2 - l1 * l1 - l2 * l2) / (2 * l1 * l2)
    if cos_knee > 1.0 + 1e-12 or cos_knee < -1.0:
        raise IkError('ankle %s m is out of the %s leg\'s reach (%.4f m from the hip, at most %.4f m)'
                      % (np.round(ankle_m, 4).tolist(), side, math.sqrt(d2), l1 + l2))
    q3 = math.acos(min(1.0, cos_knee))
    q2 = math.atan2(-p[0], reach_m) - math.atan2(l2 * math.sin(q3), l1 + l2 * math.cos(q3))
    m = rot_x(q1).T @ r0.T @ foot_rotation  # = Ry(q2 + q3 + q4) Rx(q5) when q0 is right
    pitch = math.atan2(-m[2, 0], m[0, 0])
    q5 = math.atan2(-m[1, 2], m[1, 1])
    return (q1, q2, q3, pitch - q2 - q3, q5), m[1, 0]


def solve_hip_yaw_pitch(side, ankle_m, foot_yaw_rad):
    """The HipYawPitch angle [rad] that gives the foot `foot_yaw_rad` relative to the torso."""
    foot_rotation = rot_z(foot_yaw_rad)
    lo, hi = HIP_YAW_PITCH_RANGE_RAD

    def residual(q0):
        return _below_hip(side, ankle_m, foot_rotation, q0)[1]

    f_lo, f_hi = residual(lo), residual(hi)
    if f_lo * f_hi > 0:
        raise IkError('foot yaw %.3f rad of the %s leg is out of the HipYawPitch range' % (foot_yaw_rad, side))
    for _ in range(60):  # bisection: 1.9 rad / 2^60, far below any motor's resolution
        mid = 0.5 * (lo + hi)
        f_mid = residual(mid)
        if f_lo * f_mid <= 0:
            hi = mid
        else:
            lo, f_lo = mid, f_mid
    return 0.5 * (lo + hi)


def inverse(side, ankle_m, foot_yaw_rad=0.0, hip_yaw_pitch_rad=None):
    """Six leg angles [rad] (LEG_JOINTS order) putting the ankle point at `ankle_m` (torso frame)
    with the sole flat and yawed `foot_yaw_rad` relative to the torso. `hip_yaw_pitch_rad` imposes
    HipYawPitch (the two hips share one motor); the foot yaw is then met as closely as the chain
    below allows. Raises IkError out of reach."""
    if hip_yaw_pitch_rad is None:
        hip_yaw_pitch_rad = 0.0 if foot_yaw_rad == 0.0 else solve_hip_yaw_pitch(side, ankle_m, foot_yaw_rad)
    below, _ = _below_hip(side, ankle_m, rot_z(foot_yaw_rad), hip_yaw_pitch_rad)
    return (hip_yaw_pitch_rad,) + below


def inverse_pair(left_ankle_m, left_yaw_rad, right_ankle_m, right_yaw_rad):
    """{joint name: angle [rad]} of both legs with one shared HipYawPitch (the mean of the two
    legs' own solutions; equal when the feet are yawed symmetrically about the torso)."""
    q0 = 0.0
    if left_yaw_rad != 0.0 or right_yaw_rad != 0.0:
        q0 = 0.5 * (solve_hip_yaw_pitch('L', left_ankle_m, left_yaw_rad)
                    + solve_hip_yaw_pitch('R', right_ankle_m, right_yaw_rad))
    angles = {}
    for side, ankle, yaw in (('L', left_ankle_m, left_yaw_rad), ('R', right_ankle_m, right_yaw_rad)):
        for name, angle in zip(LEG_JOINTS, inverse(side, ankle, yaw, q0)):
            angles[side + name] = angle
    return angles
