"""What the robot-description tests share: xacro run with this package first on
ROS_PACKAGE_PATH (so `$(find conde_description)` resolves to it), a cache of expanded robots, and
lookups into the parsed URDF."""

import os
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
