"""The wheel file of major_ackermann_controller (conde_major/controller_config.py): the shipped
file, and the exact message for each way a file can be wrong (file and field named)."""

import os

import pytest

from conde_major.controller_config import ConfigError, Wheel, load_wheel_config, parse_wheel_config

CONFIG_DIR = os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), 'config')
SHIPPED = os.path.join(CONFIG_DIR, 'major_ackermann_controller.yaml')

GOOD = """
left_front_wheel: {steering_link_name: lf, steering_controller_name: ls, axle_controller_name: lfa, diameter: 0.1}
right_front_wheel: {steering_link_name: rf, steering_controller_name: rs, axle_controller_name: rfa, diameter: 0.1}
left_rear_wheel: {link_name: lr, axle_controller_name: lra, diameter: 0.12}
right_rear_wheel: {link_name: rr, axle_controller_name: rra, diameter: 0.12}
"""


def test_the_shipped_file_has_the_originals_names_and_diameters():
    c = load_wheel_config(SHIPPED)
    assert c.left_front == Wheel('left_front_wheel', 'left_front_wheel_ctrlr', 0.1, 'left_steering_ctrlr')
    assert c.right_front == Wheel('right_front_wheel', 'right_front_wheel_ctrlr', 0.1, 'right_steering_ctrlr')
    assert c.left_rear == Wheel('left_rear_wheel', 'left_rear_wheel_ctrlr', 0.1)
    assert c.right_rear == Wheel('right_rear_wheel', 'right_rear_wheel_ctrlr', 0.1)
    assert [name for _, name in c.controllers()] == [
        'left_steering_ctrlr', 'right_steering_ctrlr', 'left_front_wheel_ctrlr', 'right_front_wheel_ctrlr',
        'left_rear_wheel_ctrlr', 'right_rear_wheel_ctrlr']


def test_a_good_text():
    c = parse_wheel_config(GOOD, 'x.yaml')
    assert c.left_rear.diameter_m == 0.12 and c.right_front.steering_controller == 'rs'


@pytest.mark.parametrize('old, new, message', [
    ('steering_controller_name: ls, ', '',
     "f.yaml: left_front_wheel/steering_controller_name: required key is missing "
     "(the hinge's JointPositionController)"),
    ('axle_controller_name: rra, ', '',
     "f.yaml: right_rear_wheel/axle_controller_name: required key is missing (the wheel's JointVelocityController)"),
    ('axle_controller_name: lfa', 'axle_controller_name: ',
     "f.yaml: left_front_wheel/axle_controller_name: expected a name (the wheel's JointVelocityController), "
     "got NoneType None"),
    ('link_name: lr', 'link_name: 3',
     "f.yaml: left_rear_wheel/link_name: expected a name (the wheel's link), got int 3"),
    ('diameter: 0.12}\nright', 'diameter: -0.12}\nright',
     'f.yaml: left_rear_wheel/diameter: expected a positive number of metres, got float -0.12'),
    ('diameter: 0.1}\nright_front', 'diameter: wide}\nright_front',
     "f.yaml: left_front_wheel/diameter: expected a positive number of metres, got str 'wide'"),
    ('link_name: rr,', 'link_name: rr, mass: 1,',
     'f.yaml: right_rear_wheel/mass: unknown key (expected one of: link_name, axle_controller_name, diameter)'),
    ('rra', 'lra',
     "f.yaml: right_rear_wheel/axle_controller_name: controller 'lra' is already used by "
     "left_rear_wheel/axle_controller_name"),
    ('left_rear_wheel:', 'shock_absorbers: []\nleft_rear_wheel:',
     'f.yaml: shock_absorbers: unknown key (expected one of: left_front_wheel, right_front_wheel, '
     'left_rear_wheel, right_rear_wheel)'),
    ('right_rear_wheel: {link_name: rr, axle_controller_name: rra, diameter: 0.12}', '',
     'f.yaml: right_rear_wheel: required entry is missing (keys: link_name, axle_controller_name, diameter)'),
    ('right_rear_wheel: {link_name: rr, axle_controller_name: rra, diameter: 0.12}', 'right_rear_wheel: rr',
     "f.yaml: right_rear_wheel: expected a dictionary (keys: link_name, axle_controller_name, diameter), "
     "got str 'rr'"),
])
def test_each_mistake_names_the_file_and_the_field(old, new, message):
    assert old in GOOD
    with pytest.raises(ConfigError) as e:
        parse_wheel_config(GOOD.replace(old, new, 1), 'f.yaml')
    assert str(e.value) == message


def test_not_a_dictionary_and_malformed_yaml():
    with pytest.raises(ConfigError) as e:
        parse_wheel_config('- a\n- b\n', 'f.yaml')
    assert str(e.value) == ("f.yaml: expected a dictionary with left_front_wheel, right_front_wheel, "
                            "left_rear_wheel, right_rear_wheel, got list ['a', 'b']")
    with pytest.raises(ConfigError) as e:
        parse_wheel_config('left_front_wheel: {a: 1\nright_front_wheel: 2\n', 'f.yaml')
    assert str(e.value) == "f.yaml:2: malformed YAML: expected ',' or '}', but got ':'"


def test_a_missing_file(tmp_path):
    path = str(tmp_path / 'nothing.yaml')
    with pytest.raises(ConfigError) as e:
        load_wheel_config(path)
    assert str(e.value) == '%s: cannot read the file: No such file or directory' % path
