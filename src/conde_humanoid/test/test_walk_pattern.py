"""The walk pattern (conde_humanoid/walk_pattern.py, swing.py, walk_requests.py): joint angles in
the motors' ranges, the feet where the plan puts them, and the requests nao_walk refuses."""

import math

import numpy as np
import pytest

from conde_humanoid import footsteps as fs
from conde_humanoid.swing import blend, swing_pose
from conde_humanoid.walk_pattern import GaitParameters, generate
from conde_humanoid.walk_requests import WalkPlanner, WalkRequestError

# Leg ranges [rad] of urdf/robots/nao.urdf.xacro (left; the right mirrors roll).
LIMITS = {'HipYawPitch': (-1.14529, 0.740718), 'HipPitch': (-1.53589, 0.48398), 'KneePitch': (-0.0923279, 2.11255),
          'AnklePitch': (-1.18944, 0.922581)}


def test_swing_leaves_and_lands_flat_at_rest():
    assert blend(0) == 0 and blend(1) == 1 and blend(0.5) == pytest.approx(0.5)
    assert swing_pose((0, 0, 0), (0.04, 0, 0.2), 0.02, 0.5)[2] == pytest.approx(0.02)
    assert swing_pose((0, 0, 0), (0.04, 0, 0.2), 0.02, 1.0) == pytest.approx((0.04, 0, 0, 0.2))


@pytest.mark.parametrize('kind', ['straight', 'turn'])
def test_pattern_stays_in_the_joint_ranges_and_follows_the_plan(kind):
    params = GaitParameters()
    feet = fs.standing_feet(fs.Pose2D(), params.foot_separation_m)
    if kind == 'straight':
        steps = fs.plan_straight(0.3, params.max_step_length_m, params.foot_separation_m)
    else:
        steps = fs.plan_turn(math.pi / 2, params.max_step_turn_rad, params.foot_separation_m)
    pattern = generate(feet, steps, params)
    duration = params.start_s + len(steps) * params.step_period_s + params.double_support_s + params.end_s
    assert pattern.time_s[-1] == pytest.approx(duration - params.control_period_s)
    for name, (lo, hi) in LIMITS.items():
        for side in 'LR':
            values = pattern.joints[side + name]
            assert values.min() >= lo and values.max() <= hi, side + name
    np.testing.assert_array_equal(pattern.joints['LHipYawPitch'], pattern.joints['RHipYawPitch'])
    assert np.abs(pattern.zmp_m - pattern.zmp_ref_m).max() < 0.02
    by_side = {s.side: s for s in steps[-2:]}
    assert pattern.feet_end == (by_side['L'], by_side['R'])


def test_walk_to_requests_move_the_planned_body():
    planner = WalkPlanner()
    planner.plan_walk_to(0.1, 0.0, 0.5)
    assert planner.body.x_m == pytest.approx(0.1)
    planner.plan_walk_to(0.0, math.pi / 2, 1.0)
    assert planner.body.yaw_rad == pytest.approx(math.pi / 2)
    assert planner.body.x_m == pytest.approx(0.1)


@pytest.mark.parametrize('distance, angle, fraction, message', [
    (0.1, 0.2, 0.5, 'exactly one of distance_m and angle_rad'),
    (0.0, 0.0, 0.5, 'exactly one of distance_m and angle_rad'),
    (0.1, 0.0, 0.0, r'speed_fraction must be in \(0, 1\]'),
    (0.1, 0.0, 1.5, r'speed_fraction must be in \(0, 1\]'),
    (float('nan'), 0.0, 0.5, 'must be finite'),
])
def test_bad_requests_are_refused_with_a_reason(distance, angle, fraction, message):
    with pytest.raises(WalkRequestError, match=message):
        WalkPlanner().plan_walk_to(distance, angle, fraction)


def test_velocity_bursts_are_clamped_to_the_maximum():
    planner = WalkPlanner()
    planner.plan_velocity(1.0, 0.0, 0.0, steps=4)
    assert planner.body.x_m == pytest.approx(4 * GaitParameters().max_step_length_m)
