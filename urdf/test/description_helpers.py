"""What the robot-description tests share: xacro run with this package first on
ROS_PACKAGE_PATH (so `$(find conde_description)` resolves to it), a cache of expanded robots, and
lookups into the parsed URDF."""

import os
import shutil
import subprocess
import xml.etree.ElementTree as ET

import numpy as np

from conde_testing.ros_harness import xacro_finding

PACKAGE_DIR = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
xacro = xacro_finding(PACKAGE_DIR)


class XacroRobot:
    """One robot file of robots/: its URDF text and parsed tree per set of xacro args."""

    def __init__(self, file_name):
        self.path = os.path.join(PACKAGE_DIR, 'robots', file_name)
        self._trees = {}

    def process(self, **args):
        """Runs xacro on the robot file with the given args; returns the URDF text."""
        return xacro.process_file(self.path, mappings=dict(args)).toprettyxml(indent='  ')

    def robot(self, **args):
        """The parsed URDF (cached per set of args)."""
        key = tuple(sorted(args.items()))
        if key not in self._trees:
            self._trees[key] = ET.fromstring(self.process(**args))
        return self._trees[key]


def args_id(args):
    """A test id for a set of xacro args: 'name=value,...', or 'defaults'."""
    return ','.join('%s=%s' % kv for kv in sorted(args.items())) or 'defaults'


def check_urdf(urdf_text, tmp_path, file_name):
    """Runs check_urdf (liburdfdom-tools) on `urdf_text`, written to tmp_path/file_name; asserts that
    it accepts it and returns what it printed."""
    check_urdf = shutil.which('check_urdf')
    assert check_urdf, 'check_urdf (liburdfdom-tools) is not installed'
    urdf_file = tmp_path / file_name
    urdf_file.write_text(urdf_text)
    result = subprocess.run([check_urdf, str(urdf_file)], capture_output=True, text=True)
    assert result.returncode == 0, result.stdout + result.stderr
    return result.stdout


def assert_no_leftover_xacro(urdf_text):
    assert 'xacro:' not in urdf_text.replace('xmlns:xacro', '')
    assert '${' not in urdf_text and '$(' not in urdf_text


def parent_links(root):
    """child link name -> parent link name, over every joint."""
    return {j.find('child').get('link'): j.find('parent').get('link') for j in root.findall('joint')}


def assert_frame_tree(root, root_link, parent_of):
    """The joints make one tree hanging from root_link, in which each link of `parent_of` (link
    name -> parent link name) hangs from its parent."""
    parents = parent_links(root)
    assert set(links(root)) - set(parents) == {root_link}
    for link, parent in parent_of.items():
        assert parents[link] == parent, link


def movable_joints(root):
    """Names of the joints that are not fixed."""
    return {n for n, j in joints(root).items() if j.get('type') != 'fixed'}


def floats(text):
    return np.array([float(v) for v in text.split()])


def links(root):
    return {link.get('name'): link for link in root.findall('link')}


def joints(root):
    return {joint.get('name'): joint for joint in root.findall('joint')}


def mass(link):
    inertial = link.find('inertial')
    return 0.0 if inertial is None else float(inertial.find('mass').get('value'))


def plugin_params(root, filename):
    found = [p for p in root.iter('plugin') if p.get('filename') == filename]
    assert len(found) == 1, filename
    return {c.tag: (c.text or '').strip() for c in found[0]}
