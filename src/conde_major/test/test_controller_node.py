"""major_ackermann_controller against a real roscore on a free loopback port: each start-up
problem stops it with exit status 1 and one line naming the file or parameter and the field.
(The node driving the simulated robot: tests/major_alvega.test.)"""

import os
import subprocess

import pytest
import yaml

from conde_testing.ros_harness import Roscore

PACKAGE_DIR = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
WORKSPACE = os.path.normpath(os.path.join(PACKAGE_DIR, '..', '..'))
CONFIG = os.path.join(PACKAGE_DIR, 'config', 'major_ackermann_controller.yaml')
JOINT_CONTROLLERS = os.path.join(PACKAGE_DIR, 'config', 'major_joint_states.yaml')
XACRO = os.path.join(WORKSPACE, 'urdf', 'robots', 'major_alvega.urdf.xacro')
NODE = 'major_ackermann_controller'


@pytest.fixture(scope='module')
def core():
    with Roscore('conde_major') as core:
        yield core


@pytest.fixture(scope='module')
def robot_description(core):
    return subprocess.run(['xacro', XACRO, 'cameras:=false'], env=core.env, capture_output=True, text=True,
                          check=True).stdout


@pytest.fixture(scope='module')
def joint_controllers():
    with open(JOINT_CONTROLLERS) as f:
        return {'/' + name: value for name, value in yaml.safe_load(f).items()}


def reset_params(core, params):
    """Clears what the tests set on the parameter server, then sets `params`."""
    core.set_params(params, clear=core.param_namespaces())


def run_node(core, *args):
    return subprocess.run(['rosrun', 'conde_major', NODE, '__name:=ackermann_controller'] + list(args),
                          env=core.env, capture_output=True, text=True, timeout=120)


def error_lines(stderr):
    return [line for line in stderr.splitlines() if line.startswith(NODE + ': error: ')]


def write_config(tmp_path, text):
    path = tmp_path / 'wheels.yaml'
    path.write_text(text)
    return str(path)


def shipped_config():
    with open(CONFIG) as f:
        return f.read()


@pytest.mark.parametrize('old, new, field, what', [
    ('  steering_controller_name: left_steering_ctrlr\n', '', 'left_front_wheel/steering_controller_name',
     "required key is missing (the hinge's JointPositionController)"),
    ('axle_controller_name: right_rear_wheel_ctrlr', 'axle_controller_name:', 'right_rear_wheel/axle_controller_name',
     "expected a name (the wheel's JointVelocityController), got NoneType None"),
])
def test_a_wheel_file_without_a_controller_name(core, robot_description, joint_controllers, tmp_path, old, new,
                                                field, what):
    reset_params(core, dict(joint_controllers, **{'/robot_description': robot_description}))
    text = shipped_config()
    assert old in text
    path = write_config(tmp_path, text.replace(old, new))
    proc = run_node(core, '_config_file:=' + path)
    assert proc.returncode == 1
    assert error_lines(proc.stderr) == ['%s: error: %s: %s: %s' % (NODE, path, field, what)]


def test_a_controller_that_is_not_configured(core, robot_description, joint_controllers, tmp_path):
    reset_params(core, dict(joint_controllers, **{'/robot_description': robot_description}))
    path = write_config(tmp_path, shipped_config().replace('left_rear_wheel_ctrlr', 'left_rear_ctrlr'))
    proc = run_node(core, '_config_file:=' + path)
    assert proc.returncode == 1
    assert error_lines(proc.stderr) == [
        "%s: error: %s: left_rear_wheel/axle_controller_name: controller 'left_rear_ctrlr' is not configured "
        "(no parameter /left_rear_ctrlr/type: load the controller YAML, e.g. major_joint_states.yaml, into this "
        "namespace)" % (NODE, path)]


def test_a_link_the_robot_does_not_have(core, robot_description, joint_controllers, tmp_path):
    reset_params(core, dict(joint_controllers, **{'/robot_description': robot_description}))
    path = write_config(tmp_path, shipped_config().replace('steering_link_name: right_front_wheel',
                                                           'steering_link_name: right_front_tyre'))
    proc = run_node(core, '_config_file:=' + path)
    assert proc.returncode == 1
    assert error_lines(proc.stderr) == [
        "%s: error: parameter /robot_description (links named in %s): the URDF has no link named "
        "'right_front_tyre'" % (NODE, path)]


@pytest.mark.parametrize('params, args, message', [
    ({}, [], 'parameter /ackermann_controller/config_file is required: the wheel file, e.g. '
             '$(find conde_major)/config/major_ackermann_controller.yaml'),
    ({}, ['_config_file:=/no/such/wheels.yaml'],
     '/no/such/wheels.yaml: cannot read the file: No such file or directory'),
    ({'/robot_description': None}, ['_config_file:=' + CONFIG],
     'parameter /robot_description: not set (the robot URDF is needed for the wheelbase and the track)'),
    ({}, ['_config_file:=' + CONFIG, '_cmd_timeout:=-1'],
     'parameter /ackermann_controller/cmd_timeout: expected a number >= 0 [s] (0 = never), got -1'),
    ({}, ['_config_file:=' + CONFIG, '_publishing_frequency:=fast'],
     "parameter /ackermann_controller/publishing_frequency: expected a number > 0 [Hz], got 'fast'"),
    ({}, ['_config_file:=' + CONFIG, '_publishing_frequency:=0'],
     'parameter /ackermann_controller/publishing_frequency: expected a number > 0 [Hz], got 0'),
])
def test_bad_parameters(core, robot_description, joint_controllers, params, args, message):
    setup = dict(joint_controllers, **{'/robot_description': robot_description})
    setup.update(params)
    reset_params(core, {k: v for k, v in setup.items() if v is not None})
    proc = run_node(core, *args)
    assert proc.returncode == 1
    assert error_lines(proc.stderr) == ['%s: error: %s' % (NODE, message)]
