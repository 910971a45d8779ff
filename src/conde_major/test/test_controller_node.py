"""major_ackermann_controller against a real roscore on a free loopback port: each start-up
problem stops it with exit status 1 and one line naming the file or parameter and the field.
(The node driving the simulated robot: tests/major_alvega.test.)"""

import os
import socket
import subprocess
import time

import pytest
import yaml

PACKAGE_DIR = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
WORKSPACE = os.path.normpath(os.path.join(PACKAGE_DIR, '..', '..'))
CONFIG = os.path.join(PACKAGE_DIR, 'config', 'major_ackermann_controller.yaml')
JOINT_CONTROLLERS = os.path.join(PACKAGE_DIR, 'config', 'major_joint_states.yaml')
XACRO = os.path.join(WORKSPACE, 'urdf', 'robots', 'major_alvega.urdf.xacro')
NODE = 'major_ackermann_controller'


def workspace_env():
    """The environment in which the built workspace's nodes run."""
    env = dict(os.environ, PATH='/usr/bin:' + os.environ.get('PATH', ''))
    if subprocess.run(['rospack', 'find', 'conde_major'], env=env, capture_output=True).returncode == 0:
        return env
    setup = os.path.join(WORKSPACE, 'devel', 'setup.bash')
    assert os.path.isfile(setup), 'build the workspace first (scripts/build.sh): no %s' % setup
    out = subprocess.run(['bash', '-c', "set +u; source '%s' && env -0" % setup], env=env, capture_output=True,
                         check=True).stdout
    return dict(item.split('=', 1) for item in out.decode().split('\0') if '=' in item)


class Roscore:
    """roscore on a free port; `env` runs processes against it."""

    def __init__(self):
        with socket.socket() as s:
            s.bind(('127.0.0.1', 0))
            port = s.getsockname()[1]
        self.env = dict(workspace_env(), ROS_MASTER_URI='http://127.0.0.1:%d' % port, ROS_IP='127.0.0.1')
        self.env.pop('ROS_HOSTNAME', None)
        self.proc = subprocess.Popen(['roscore', '-p', str(port)], env=self.env, stdout=subprocess.DEVNULL,
                                     stderr=subprocess.DEVNULL)
        deadline = time.monotonic() + 60
        while subprocess.run(['rosparam', 'list'], env=self.env, capture_output=True).returncode != 0:
            assert self.proc.poll() is None, 'roscore exited'
            assert time.monotonic() < deadline, 'roscore did not come up'
            time.sleep(0.2)
        import rosgraph  # here: the other tests of the package must not need ROS
        self.master = rosgraph.Master('/test_setup', master_uri=self.env['ROS_MASTER_URI'])

    def set_params(self, params):
        """Clears what the tests set on the parameter server, then sets `params`."""
        tops = {'/' + name.split('/')[1] for name in self.master.getParamNames()}
        for top in tops - {'/rosdistro', '/rosversion', '/run_id', '/roslaunch'}:
            self.master.deleteParam(top)
        for name, value in params.items():
            self.master.setParam(name, value)

    def stop(self):
        self.proc.terminate()
        self.proc.wait(timeout=30)


@pytest.fixture(scope='module')
def core():
    core = Roscore()
    yield core
    core.stop()


@pytest.fixture(scope='module')
def robot_description(core):
    return subprocess.run(['xacro', XACRO, 'cameras:=false'], env=core.env, capture_output=True, text=True,
                          check=True).stdout


@pytest.fixture(scope='module')
def joint_controllers():
    with open(JOINT_CONTROLLERS) as f:
        return {'/' + name: value for name, value in yaml.safe_load(f).items()}


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
    core.set_params(dict(joint_controllers, **{'/robot_description': robot_description}))
    text = shipped_config()
    assert old in text
    path = write_config(tmp_path, text.replace(old, new))
    proc = run_node(core, '_config_file:=' + path)
    assert proc.returncode == 1
    assert error_lines(proc.stderr) == ['%s: error: %s: %s: %s' % (NODE, path, field, what)]


def test_a_controller_that_is_not_configured(core, robot_description, joint_controllers, tmp_path):
    core.set_params(dict(joint_controllers, **{'/robot_description': robot_description}))
    path = write_config(tmp_path, shipped_config().replace('left_rear_wheel_ctrlr', 'left_rear_ctrlr'))
    proc = run_node(core, '_config_file:=' + path)
    assert proc.returncode == 1
    assert error_lines(proc.stderr) == [
        "%s: error: %s: left_rear_wheel/axle_controller_name: controller 'left_rear_ctrlr' is not configured "
        "(no parameter /left_rear_ctrlr/type: load the controller YAML, e.g. major_joint_states.yaml, into this "
        "namespace)" % (NODE, path)]


def test_a_link_the_robot_does_not_have(core, robot_description, joint_controllers, tmp_path):
    core.set_params(dict(joint_controllers, **{'/robot_description': robot_description}))
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
    core.set_params({k: v for k, v in setup.items() if v is not None})
    proc = run_node(core, *args)
    assert proc.returncode == 1
    assert error_lines(proc.stderr) == ['%s: error: %s' % (NODE, message)]
