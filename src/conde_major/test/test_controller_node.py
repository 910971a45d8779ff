"""major_ackermann_controller against a real roscore on a free loopback port: each start-up
problem stops it with exit status 1 and one line naming the file or parameter and the field.
(The node driving the simulated robot: tests/major_alvega.test.) cmd_vel_to_ackermann: the period
of its steering rate limit is the controller's own rate (~command_rate_param), a missing, bad or
doubly given period is named. (The adapter driving the robot: tests/test_major_alvega_d1.py.)"""

import os
import select
import subprocess
import time

import pytest
import yaml

from conde_testing.ros_harness import Roscore, stop_process

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


# --- cmd_vel_to_ackermann (the adapter of the Conde stack): the period of its steering rate limit ---

ADAPTER = 'cmd_vel_to_ackermann'


def start_adapter(core, robot_description, joint_controllers, params, *args):
    reset_params(core, dict(joint_controllers, **{'/robot_description': robot_description}, **params))
    # unbuffered: its log lines reach the pipe as they are written (a clean environment has no PYTHONUNBUFFERED)
    return subprocess.Popen(['rosrun', 'conde_major', ADAPTER, '_config_file:=' + CONFIG] + list(args),
                            env=dict(core.env, PYTHONUNBUFFERED='1'), stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                            text=True, start_new_session=True)


def test_the_adapters_command_period_is_the_controllers_rate(core, robot_description, joint_controllers):
    """~command_rate_param names the parameter of the rate conde_control publishes cmd_vel at."""
    proc = start_adapter(core, robot_description, joint_controllers, {'/conde_control/rate_hz': 25},
                         '_command_rate_param:=/conde_control/rate_hz')
    try:
        deadline, line = time.monotonic() + 90, ''
        while time.monotonic() < deadline and 'command period' not in line:
            # wait for a line at most until the deadline (readline alone would block past it)
            if not select.select([proc.stdout], [], [], max(0.0, deadline - time.monotonic()))[0]:
                break
            line = proc.stdout.readline()
            if not line and proc.poll() is not None:
                break
    finally:
        stop_process(proc, timeout_s=20, group=True)
    assert 'command period 0.040000 s' in line, (line, proc.stderr.read())


@pytest.mark.parametrize('params, args, message', [
    ({}, ['_command_rate_param:=/conde_control/rate_hz'],
     'parameter /cmd_vel_to_ackermann/command_rate_param: names /conde_control/rate_hz, which is not set (the '
     'controller publishing cmd_vel sets its rate there)'),
    ({'/conde_control/rate_hz': 0}, ['_command_rate_param:=/conde_control/rate_hz'],
     'parameter /conde_control/rate_hz (named by /cmd_vel_to_ackermann/command_rate_param): expected a rate > 0 '
     '[Hz], got 0'),
    ({'/conde_control/rate_hz': 30}, ['_command_rate_param:=/conde_control/rate_hz', '_command_period_s:=0.03'],
     'parameters /cmd_vel_to_ackermann/command_period_s and /cmd_vel_to_ackermann/command_rate_param: set one of '
     'them, not both'),
])
def test_a_bad_adapter_command_period_names_the_parameter(core, robot_description, joint_controllers, params, args,
                                                          message):
    proc = start_adapter(core, robot_description, joint_controllers, params, *args)
    try:
        _, stderr = proc.communicate(timeout=90)
    finally:
        stop_process(proc, timeout_s=20, group=True)
    assert proc.returncode == 1
    assert [line for line in stderr.splitlines() if line.startswith(ADAPTER + ': error: ')] == \
        ['%s: error: %s' % (ADAPTER, message)]
