"""cmd_vel_to_ackermann against a real roscore on a free loopback port: the command period of its
steering rate limit comes from the controller's own rate parameter (~command_rate_param), and a
missing, bad or doubly given period stops it with one line naming the parameter and exit status 1.
(The adapter driving the simulated robot: tests/test_major_alvega_d1.py.)"""

import os
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
NODE = 'cmd_vel_to_ackermann'


@pytest.fixture(scope='module')
def core():
    with Roscore('conde_major_adapter') as core:
        yield core


@pytest.fixture(scope='module')
def base_params(core):
    urdf = subprocess.run(['xacro', XACRO, 'cameras:=false'], env=core.env, capture_output=True, text=True,
                          check=True).stdout
    with open(JOINT_CONTROLLERS) as f:
        params = {'/' + name: value for name, value in yaml.safe_load(f).items()}
    params['/robot_description'] = urdf
    return params


def start(core, base_params, params, *args):
    core.set_params(dict(base_params, **params), clear=core.param_namespaces())
    return subprocess.Popen(['rosrun', 'conde_major', NODE, '_config_file:=' + CONFIG] + list(args), env=core.env,
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, start_new_session=True)


def test_the_command_period_is_the_controllers_rate(core, base_params):
    proc = start(core, base_params, {'/conde_control/rate_hz': 25}, '_command_rate_param:=/conde_control/rate_hz')
    try:
        deadline, line = time.monotonic() + 90, ''
        while time.monotonic() < deadline and 'command period' not in line:
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
def test_a_bad_command_period_names_the_parameter(core, base_params, params, args, message):
    proc = start(core, base_params, params, *args)
    try:
        _, stderr = proc.communicate(timeout=90)
    finally:
        stop_process(proc, timeout_s=20, group=True)
    assert proc.returncode == 1
    assert [line for line in stderr.splitlines() if line.startswith(NODE + ': error: ')] == \
        ['%s: error: %s' % (NODE, message)]
