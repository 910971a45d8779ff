"""Named joint poses of the NAO and the ros_control commands that hold them, free of ROS.

A pose file maps pose names to {joint: angle [rad]}; a controller file is the ros_control YAML
(config/nao_controllers.yaml): controllers with `joint` and optional `mimic_joints`. A pose names
each degree of freedom once, by the controller's `joint`; joints it does not name get 0.
"""

import math

import yaml


class PoseError(Exception):
    """A pose or controller file that cannot be used; the message names the file and the key."""


def _load(path):
    try:
        with open(path) as f:
            data = yaml.safe_load(f)
    except (OSError, yaml.YAMLError) as e:
        raise PoseError('%s: %s' % (path, e))
    if not isinstance(data, dict):
        raise PoseError('%s: expected a dictionary at the top' % path)
    return data


def position_controllers(controllers, where='controllers'):
    """{controller name: its joint} of the position controllers of a ros_control YAML (dict)."""
    found = {}
    for name, config in controllers.items():
        if not isinstance(config, dict) or 'type' not in config:
            raise PoseError('%s: %s: expected a controller with a type' % (where, name))
        if config['type'].endswith('/JointPositionController'):
            if not isinstance(config.get('joint'), str):
                raise PoseError('%s: %s/joint: expected a joint name' % (where, name))
            found[name] = config['joint']
    return found


def pose_commands(pose, controllers, where='pose'):
    """{controller: angle [rad]} holding `pose` ({joint: angle}) with `controllers` (controller ->
    joint). A joint no controller drives by its `joint` key is an error naming it."""
    by_joint = {joint: name for name, joint in controllers.items()}
    commands = {name: 0.0 for name in controllers}
    for joint, angle in pose.items():
        if joint not in by_joint:
            raise PoseError("%s: %s: no position controller has joint '%s' (a mimic joint follows its master)"
                            % (where, joint, joint))
        if isinstance(angle, bool) or not isinstance(angle, (int, float)) or not math.isfinite(angle):
            raise PoseError('%s: %s: expected an angle [rad], got %r' % (where, joint, angle))
        commands[by_joint[joint]] = float(angle)
    return commands


def load_pose(poses_file, pose_name):
    """{joint: angle [rad]} of pose `pose_name` of `poses_file` (only the joints it names)."""
    poses = _load(poses_file)
    if pose_name not in poses:
        raise PoseError("%s: no pose '%s' (poses: %s)" % (poses_file, pose_name, ', '.join(sorted(poses))))
    pose = poses[pose_name] or {}
    if not isinstance(pose, dict):
        raise PoseError('%s: %s: expected {joint: angle}' % (poses_file, pose_name))
    return pose


def load_pose_commands(poses_file, pose_name, controllers_file):
    """The commands of pose `pose_name` of `poses_file` for the controllers of `controllers_file`."""
    pose = load_pose(poses_file, pose_name)
    controllers = position_controllers(_load(controllers_file), controllers_file)
    return pose_commands(pose, controllers, '%s: %s' % (poses_file, pose_name))
