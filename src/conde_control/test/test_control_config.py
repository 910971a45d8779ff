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


@pytest.mark.parametrize("text, message", [
    ("max_linear_mps: 0.4\nmax_speed: 2\n", f"unknown key 'max_speed' (expected one of: {KEYS})"),
    ("max_angular_accel_radps2: -3\n", "max_angular_accel_radps2: a limit must be > 0, got -3"),
    ("max_linear_mps: 0\n", "max_linear_mps: a limit must be > 0, got 0"),
    ("heading_gain_per_m: -1.5\n", "heading_gain_per_m: a gain must be >= 0, got -1.5"),
    ("max_linear_mps: fast\n", "max_linear_mps: expected a finite number, got 'fast'"),
    ("max_linear_mps: true\n", "max_linear_mps: expected a finite number, got True"),
    ("max_linear_mps: .nan\n", "max_linear_mps: expected a finite number, got nan"),
    ("max_linear_mps: [1, 2]\n", "max_linear_mps: expected a finite number, got [1, 2]"),
    ("- max_linear_mps: 1\n", "expected a mapping of gains and limits, got list"),
], ids=["unknown_key", "negative_limit", "zero_limit", "negative_gain", "not_a_number-fast", "not_a_number-true",
        "not_a_number-nan", "not_a_number-list", "not_a_mapping"])
def test_bad_file_names_itself_and_the_problem(tmp_path, text, message):
    path = write(tmp_path, text)
    assert error_of(path) == f"{path}: {message}"


def test_missing_file(tmp_path):
    path = str(tmp_path / "nope.yaml")
    assert error_of(path) == f"{path}: cannot read the control configuration: No such file or directory"


def test_yaml_syntax_error(tmp_path):
    path = write(tmp_path, "max_linear_mps: [1\n")
    assert error_of(path) == f"{path}:2: YAML error: expected ',' or ']', but got '<stream end>'"  # and the line
