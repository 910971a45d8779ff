"""Named poses (conde_humanoid/poses.py): the shipped stand pose against the shipped controllers,
and the message for each way a pose can be wrong."""

import os

import pytest

from conde_humanoid.poses import PoseError, load_pose_commands, pose_commands

CONFIG_DIR = os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), 'config')
POSES = os.path.join(CONFIG_DIR, 'nao_poses.yaml')
CONTROLLERS = os.path.join(CONFIG_DIR, 'nao_controllers.yaml')


def test_stand_commands_every_controller():
    commands = load_pose_commands(POSES, 'stand', CONTROLLERS)
    assert len(commands) == 25
    assert commands['LKneePitch_position_controller'] == 0.7
    assert commands['HipYawPitch_position_controller'] == 0.0
    assert commands['HeadYaw_position_controller'] == 0.0


def test_zero_pose_is_all_zero():
    assert set(load_pose_commands(POSES, 'zero', CONTROLLERS).values()) == {0.0}


def test_unknown_pose_names_the_file_and_the_poses():
    with pytest.raises(PoseError, match="nao_poses.yaml: no pose 'crouch' \\(poses: stand, zero\\)"):
        load_pose_commands(POSES, 'crouch', CONTROLLERS)


@pytest.mark.parametrize('pose, message', [
    ({'RHipYawPitch': 0.1}, "p: RHipYawPitch: no position controller has joint 'RHipYawPitch'"),
    ({'Knee': 0.1}, "p: Knee: no position controller has joint 'Knee'"),
    ({'HeadYaw': 'left'}, "p: HeadYaw: expected an angle \\[rad\\], got 'left'"),
    ({'HeadYaw': float('nan')}, "p: HeadYaw: expected an angle"),
])
def test_bad_poses(pose, message):
    with pytest.raises(PoseError, match=message):
        pose_commands(pose, {'HeadYaw_c': 'HeadYaw', 'HipYawPitch_c': 'LHipYawPitch'}, 'p')
