"""The control YAML is read strictly: exact messages for each kind of bad file."""

import os

import pytest

from conde_control.control_law import ConfigError, ControlConfig, load_config

PACKAGE_DIR = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
DEFAULT_YAML = os.path.join(PACKAGE_DIR, "config", "control.yaml")
KEYS = ("offset_gain_per_m2, heading_gain_per_m, max_linear_mps, max_angular_radps, max_linear_accel_mps2, "
        "max_angular_accel_radps2")


def write(tmp_path, text, name="control.yaml"):
    path = tmp_path / name
    path.write_text(text)
    return str(path)


def error_of(path):
    with pytest.raises(ConfigError) as info:
        load_config(path)
    return str(info.value)


def test_package_config_is_the_dataclass_default():
    # One source of truth: the shipped YAML spells out the defaults.
    assert load_config(DEFAULT_YAML) == ControlConfig()


def test_missing_keys_keep_defaults(tmp_path):
    config = load_config(write(tmp_path, "max_linear_mps: 0.4\n"))
    assert config.max_linear_mps == 0.4
    assert config.offset_gain_per_m2 == ControlConfig().offset_gain_per_m2
    assert load_config(write(tmp_path, "", "empty.yaml")) == ControlConfig()


def test_unknown_key(tmp_path):
    path = write(tmp_path, "max_linear_mps: 0.4\nmax_speed: 2\n")
    assert error_of(path) == f"{path}: unknown key 'max_speed' (expected one of: {KEYS})"


def test_negative_limit(tmp_path):
    path = write(tmp_path, "max_angular_accel_radps2: -3\n")
    assert error_of(path) == f"{path}: max_angular_accel_radps2: a limit must be > 0, got -3"


def test_zero_limit(tmp_path):
    path = write(tmp_path, "max_linear_mps: 0\n")
    assert error_of(path) == f"{path}: max_linear_mps: a limit must be > 0, got 0"


def test_negative_gain(tmp_path):
    path = write(tmp_path, "heading_gain_per_m: -1.5\n")
    assert error_of(path) == f"{path}: heading_gain_per_m: a gain must be >= 0, got -1.5"


@pytest.mark.parametrize("text, shown", [("fast", "'fast'"), ("true", "True"), (".nan", "nan"), ("[1, 2]", "[1, 2]")])
def test_not_a_number(tmp_path, text, shown):
    path = write(tmp_path, f"max_linear_mps: {text}\n")
    assert error_of(path) == f"{path}: max_linear_mps: expected a finite number, got {shown}"


def test_not_a_mapping(tmp_path):
    path = write(tmp_path, "- max_linear_mps: 1\n")
    assert error_of(path) == f"{path}: expected a mapping of gains and limits, got list"


def test_missing_file(tmp_path):
    path = str(tmp_path / "nope.yaml")
    assert error_of(path) == f"{path}: cannot read: No such file or directory"


def test_yaml_syntax_error(tmp_path):
    path = write(tmp_path, "max_linear_mps: [1\n")
    assert error_of(path).startswith(f"{path}: YAML error: ")
