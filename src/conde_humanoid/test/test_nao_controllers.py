"""The NAO's controller YAMLs (config/nao_controllers.yaml, nao_trajectory_controller.yaml) against its description
(conde_description's robots/nao.urdf.xacro): one position controller per degree of freedom, every
movable joint driven exactly once, RHipYawPitch coupled to LHipYawPitch."""

import os
import xml.etree.ElementTree as ET

import rospkg
import yaml

from conde_testing.ros_harness import xacro_finding

CONFIG_DIR = os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), 'config')
CONFIG = os.path.join(CONFIG_DIR, 'nao_controllers.yaml')
TRAJECTORY_CONFIG = os.path.join(CONFIG_DIR, 'nao_trajectory_controller.yaml')


def nao_urdf():
    description = rospkg.RosPack().get_path('conde_description')
    xacro = xacro_finding(description)
    document = xacro.process_file(os.path.join(description, 'robots', 'nao.urdf.xacro'), mappings={})
    return ET.fromstring(document.toprettyxml())


def load(path=CONFIG):
    with open(path) as f:
        return yaml.safe_load(f)


def test_every_movable_joint_is_driven_once():
    movable = {j.get('name') for j in nao_urdf().findall('joint') if j.get('type') != 'fixed'}
    driven = []
    for name, controller in load().items():
        if controller['type'] == 'joint_state_controller/JointStateController':
            continue
        assert controller['type'] == 'position_controllers/JointPositionController', name
        assert set(controller) <= {'type', 'joint', 'mimic_joints'}, name
        driven += [controller['joint']] + controller.get('mimic_joints', [])
    assert len(driven) == len(set(driven)) == 26
    assert set(driven) == movable


def test_25_position_controllers_and_the_joint_states():
    config = load()
    assert len(config) == 26
    assert config['joint_state_controller']['publish_rate'] == 50
    assert config['HipYawPitch_position_controller'] == {
        'type': 'position_controllers/JointPositionController', 'joint': 'LHipYawPitch',
        'mimic_joints': ['RHipYawPitch']}


def test_the_trajectory_controller_drives_every_movable_joint_once():
    movable = {j.get('name') for j in nao_urdf().findall('joint') if j.get('type') != 'fixed'}
    config = load(TRAJECTORY_CONFIG)
    assert set(config) == {'joint_state_controller', 'nao_trajectory_controller'}
    trajectory = config['nao_trajectory_controller']
    assert trajectory['type'] == 'position_controllers/JointTrajectoryController'
    assert trajectory['mimic_joints'] == {'RHipYawPitch': 'LHipYawPitch'}
    driven = trajectory['joints'] + list(trajectory['mimic_joints'])
    assert len(trajectory['joints']) == 25
    assert len(driven) == len(set(driven)) and set(driven) == movable
