"""The wheel file of major_ackermann_controller (config/major_ackermann_controller.yaml), read and
checked strictly, free of ROS. Every error names the file and the field.

    left_front_wheel:  {steering_link_name, steering_controller_name, axle_controller_name, diameter}
    right_front_wheel: the same
    left_rear_wheel:   {link_name, axle_controller_name, diameter}
    right_rear_wheel:  the same

Names are URDF links and ros_control controllers; diameters are in metres.
"""

import math
from dataclasses import dataclass

from conde_common.config_files import parse_yaml, read_text

FRONT_WHEELS = ('left_front_wheel', 'right_front_wheel')
REAR_WHEELS = ('left_rear_wheel', 'right_rear_wheel')
FRONT_KEYS = {
    'steering_link_name': 'the link at the steering hinge',
    'steering_controller_name': "the hinge's JointPositionController",
    'axle_controller_name': "the wheel's JointVelocityController",
    'diameter': 'the wheel diameter [m]',
}
REAR_KEYS = {
    'link_name': "the wheel's link",
    'axle_controller_name': "the wheel's JointVelocityController",
    'diameter': 'the wheel diameter [m]',
}


class ConfigError(ValueError):
    """A problem in the wheel file; the message starts with '<file>: <field>: '."""


@dataclass(frozen=True)
class Wheel:
    link: str                 # steering_link_name (front) or link_name (rear)
    axle_controller: str
    diameter_m: float
    steering_controller: str = ''  # front wheels only


@dataclass(frozen=True)
class WheelConfig:
    left_front: Wheel
    right_front: Wheel
    left_rear: Wheel
    right_rear: Wheel

    def controllers(self):
        """(field, controller name) of the six controllers, steering first."""
        return [('left_front_wheel/steering_controller_name', self.left_front.steering_controller),
                ('right_front_wheel/steering_controller_name', self.right_front.steering_controller),
                ('left_front_wheel/axle_controller_name', self.left_front.axle_controller),
                ('right_front_wheel/axle_controller_name', self.right_front.axle_controller),
                ('left_rear_wheel/axle_controller_name', self.left_rear.axle_controller),
                ('right_rear_wheel/axle_controller_name', self.right_rear.axle_controller)]


def _describe(value):
    return '%s %r' % (type(value).__name__, value)


def _wheel(path, name, entry, keys):
    if entry is None:
        raise ConfigError('%s: %s: required entry is missing (keys: %s)' % (path, name, ', '.join(keys)))
    if not isinstance(entry, dict):
        raise ConfigError('%s: %s: expected a dictionary (keys: %s), got %s'
                          % (path, name, ', '.join(keys), _describe(entry)))
    for key in entry:
        if key not in keys:
            raise ConfigError('%s: %s/%s: unknown key (expected one of: %s)' % (path, name, key, ', '.join(keys)))
    values = {}
    for key, meaning in keys.items():
        field = '%s/%s' % (name, key)
        if key not in entry:
            raise ConfigError('%s: %s: required key is missing (%s)' % (path, field, meaning))
        value = entry[key]
        if key == 'diameter':
            if (isinstance(value, bool) or not isinstance(value, (int, float))
                    or not (math.isfinite(value) and value > 0)):
                raise ConfigError('%s: %s: expected a positive number of metres, got %s'
                                  % (path, field, _describe(value)))
            values[key] = float(value)
        else:
            if not isinstance(value, str) or not value.strip() or value != value.strip():
                raise ConfigError('%s: %s: expected a name (%s), got %s' % (path, field, meaning, _describe(value)))
            values[key] = value
    return values


def parse_wheel_config(text, path):
    """The wheel file's `text`; `path` names it in errors."""
    data = parse_yaml(text, path, ConfigError, 'malformed YAML')
    if not isinstance(data, dict):
        raise ConfigError('%s: expected a dictionary with %s, got %s'
                          % (path, ', '.join(FRONT_WHEELS + REAR_WHEELS), _describe(data)))
    for key in data:
        if key not in FRONT_WHEELS + REAR_WHEELS:
            raise ConfigError('%s: %s: unknown key (expected one of: %s)'
                              % (path, key, ', '.join(FRONT_WHEELS + REAR_WHEELS)))
    wheels = {}
    for name in FRONT_WHEELS:
        v = _wheel(path, name, data.get(name), FRONT_KEYS)
        wheels[name] = Wheel(v['steering_link_name'], v['axle_controller_name'], v['diameter'],
                             v['steering_controller_name'])
    for name in REAR_WHEELS:
        v = _wheel(path, name, data.get(name), REAR_KEYS)
        wheels[name] = Wheel(v['link_name'], v['axle_controller_name'], v['diameter'])
    config = WheelConfig(wheels['left_front_wheel'], wheels['right_front_wheel'], wheels['left_rear_wheel'],
                         wheels['right_rear_wheel'])
    seen = {}
    for field, controller in config.controllers():
        if controller in seen:
            raise ConfigError("%s: %s: controller '%s' is already used by %s"
                              % (path, field, controller, seen[controller]))
        seen[controller] = field
    return config


def load_wheel_config(path):
    """Reads and checks the wheel file at `path`."""
    return parse_wheel_config(read_text(path, ConfigError, 'the file'), path)
