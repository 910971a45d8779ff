"""The key map: every key, the steps and limits, stop, quit, ignored keys, settings validation
and the help text.  Pure Python: no ROS."""

import math

import pytest

from conde_teleop.keymap import (KEY_ACTIONS, SETTING_NAMES, Action, SettingsError, TeleopKeymap, TeleopSettings,
                                 validate)

UP, DOWN, RIGHT, LEFT = "\x1b[A", "\x1b[B", "\x1b[C", "\x1b[D"
UP_APP, DOWN_APP, RIGHT_APP, LEFT_APP = "\x1bOA", "\x1bOB", "\x1bOC", "\x1bOD"  # application cursor mode


def pressed(keys, settings=TeleopSettings()):
    keymap = TeleopKeymap(settings)
    for key in keys:
        keymap.press(key)
    return keymap.command


def test_defaults_suit_conde():
    assert TeleopSettings() == TeleopSettings(linear_step_mps=0.1, angular_step_radps=0.25, max_linear_mps=0.5,
                                              max_angular_radps=1.5)
    assert SETTING_NAMES == ("linear_step_mps", "angular_step_radps", "max_linear_mps", "max_angular_radps")
    assert TeleopKeymap().command == (0.0, 0.0)


@pytest.mark.parametrize("key, action, command", [
    ("i", Action.FASTER, (0.1, 0.0)),
    (UP, Action.FASTER, (0.1, 0.0)),
    (UP_APP, Action.FASTER, (0.1, 0.0)),
    (",", Action.SLOWER, (-0.1, 0.0)),
    (DOWN, Action.SLOWER, (-0.1, 0.0)),
    (DOWN_APP, Action.SLOWER, (-0.1, 0.0)),
    ("j", Action.LEFT, (0.0, 0.25)),
    (LEFT, Action.LEFT, (0.0, 0.25)),
    (LEFT_APP, Action.LEFT, (0.0, 0.25)),
    ("l", Action.RIGHT, (0.0, -0.25)),
    (RIGHT, Action.RIGHT, (0.0, -0.25)),
    (RIGHT_APP, Action.RIGHT, (0.0, -0.25)),
    ("k", Action.STOP, (0.0, 0.0)),
    (" ", Action.STOP, (0.0, 0.0)),
    ("q", Action.QUIT, (0.0, 0.0)),
    ("\x03", Action.QUIT, (0.0, 0.0)),
])
def test_each_key_from_standstill(key, action, command):
    keymap = TeleopKeymap()
    assert keymap.press(key) is action
    assert keymap.command == command


def test_the_table_holds_exactly_the_documented_keys():
    assert sorted(KEY_ACTIONS) == sorted(["i", UP, UP_APP, ",", DOWN, DOWN_APP, "j", LEFT, LEFT_APP, "l", RIGHT,
                                          RIGHT_APP, "k", " ", "q", "\x03"])


@pytest.mark.parametrize("key", ["x", "I", "K", "Q", "h", "\x1b", "\x1b[1;5A", "\x1bx", "\x1b[", "é", "\r", "\x04", ""])
def test_unknown_keys_are_ignored(key):
    keymap = TeleopKeymap()
    keymap.press("i")
    keymap.press("j")
    assert keymap.press(key) is None
    assert keymap.command == pytest.approx((0.1, 0.25))


def test_steps_accumulate_and_go_back_to_exactly_zero():
    keymap = TeleopKeymap()
    for _ in range(3):
        keymap.press("i")
        keymap.press("l")
    assert keymap.command == pytest.approx((0.3, -0.75))
    for _ in range(3):
        keymap.press(",")
        keymap.press("j")
    assert keymap.command == (0.0, 0.0)  # exact: counted in whole steps


@pytest.mark.parametrize("keys, command", [
    (["i"] * 5, (0.5, 0.0)),
    (["i"] * 9, (0.5, 0.0)),
    ([","] * 9, (-0.5, 0.0)),
    (["j"] * 6, (0.0, 1.5)),
    (["j"] * 20, (0.0, 1.5)),
    (["l"] * 20, (0.0, -1.5)),
])
def test_limits(keys, command):
    assert pressed(keys) == pytest.approx(command)


def test_after_the_limit_one_press_back_leaves_it():
    # Presses beyond the limit are not stored: one press back is one step below the limit.
    assert pressed(["i"] * 9 + [","]) == pytest.approx((0.4, 0.0))
    assert pressed(["l"] * 20 + ["j"]) == pytest.approx((0.0, -1.25))


def test_a_limit_that_is_not_a_whole_number_of_steps_is_reached_and_kept():
    settings = TeleopSettings(linear_step_mps=0.2, angular_step_radps=0.5, max_linear_mps=0.5,
                              max_angular_radps=0.75)
    assert pressed(["i"] * 2, settings) == pytest.approx((0.4, 0.0))
    assert pressed(["i"] * 3, settings) == pytest.approx((0.5, 0.0))
    assert pressed(["i"] * 4, settings) == pytest.approx((0.5, 0.0))
    assert pressed(["i"] * 4 + [","], settings) == pytest.approx((0.4, 0.0))
    assert pressed(["l"] * 2, settings) == pytest.approx((0.0, -0.75))
    assert pressed(["l"] * 2 + ["j"], settings) == pytest.approx((0.0, -0.5))


def test_a_limit_equal_to_whole_steps_up_to_rounding():
    # 0.3 / 0.1 is 2.9999999999999996 in floating point: still 3 steps, not 4.
    settings = TeleopSettings(linear_step_mps=0.1, max_linear_mps=0.3)
    assert pressed(["i"] * 5 + [","], settings) == pytest.approx((0.2, 0.0))
    assert pressed(["i"] * 5, settings)[0] <= 0.3


def test_a_step_equal_to_the_limit():
    settings = TeleopSettings(linear_step_mps=0.5, max_linear_mps=0.5, angular_step_radps=1.0, max_angular_radps=1.0)
    assert pressed(["i", "i", "l", "l"], settings) == (0.5, -1.0)
    assert pressed(["i", "i", ","], settings) == (0.0, 0.0)


def test_stop_keys_zero_both_commands():
    for stop_key in ("k", " "):
        keymap = TeleopKeymap()
        for key in ("i", "i", "j", "\x1b[A"):
            keymap.press(key)
        assert keymap.press(stop_key) is Action.STOP
        assert keymap.command == (0.0, 0.0)
        keymap.press("i")  # counting starts again from 0
        assert keymap.command == pytest.approx((0.1, 0.0))


def test_quit_keys_do_not_change_the_command():
    keymap = TeleopKeymap()
    keymap.press("i")
    assert keymap.press("q") is Action.QUIT
    assert keymap.command == pytest.approx((0.1, 0.0))


def test_the_same_presses_give_the_same_commands():
    keys = ["i", "i", "j", ",", "\x1b[C", "x", "\x1b[A", "\x1b[A", "\x1b[A", "\x1b[A", "l", "l", "l", "l", "l", "l",
            "l", " ", ",", "j"]
    runs = []
    for _ in range(2):
        keymap = TeleopKeymap()
        runs.append([(keymap.press(key), keymap.command) for key in keys])
    assert runs[0] == runs[1]
    assert runs[0][-1] == (Action.LEFT, pytest.approx((-0.1, 0.25)))


def test_describe_command():
    keymap = TeleopKeymap()
    assert keymap.describe_command() == "linear +0.00 m/s, angular +0.00 rad/s"
    for key in ("i", "i", "l"):
        keymap.press(key)
    assert keymap.describe_command() == "linear +0.20 m/s, angular -0.25 rad/s"


def test_help_text_names_every_key_and_the_settings():
    text = TeleopKeymap(TeleopSettings(linear_step_mps=0.2, angular_step_radps=0.3, max_linear_mps=0.8,
                                       max_angular_radps=1.2)).help_text()
    assert text.splitlines() == [
        "Conde keyboard teleop: one key at a time, no Enter.",
        "  i or Up      faster forward    linear  +0.2 m/s (up to 0.8 m/s)",
        "  , or Down    slower/backwards  linear  -0.2 m/s (down to -0.8 m/s)",
        "  j or Left    turn left         angular +0.3 rad/s (up to 1.2 rad/s)",
        "  l or Right   turn right        angular -0.3 rad/s (down to -1.2 rad/s)",
        "  k or Space   stop",
        "  q or Ctrl-C  quit (sends a stop first)",
        "Other keys are ignored.",
    ]


@pytest.mark.parametrize("name", SETTING_NAMES)
@pytest.mark.parametrize("value", [0, 0.0, -0.1, math.nan, math.inf, "fast", None, True, [0.1]])
def test_each_setting_must_be_a_finite_number_above_zero(name, value):
    with pytest.raises(SettingsError) as info:
        TeleopKeymap(TeleopSettings(**{name: value}))
    assert info.value.name == name
    assert str(info.value) == "%s: expected a number > 0, got %r" % (name, value)


def test_integer_settings_are_numbers():
    keymap = TeleopKeymap(TeleopSettings(linear_step_mps=1, max_linear_mps=2, angular_step_radps=1,
                                         max_angular_radps=3))
    for key in ("i", "i", "i", "j"):
        keymap.press(key)
    assert keymap.command == (2, 1)


def test_a_step_larger_than_its_limit():
    with pytest.raises(SettingsError) as info:
        validate(TeleopSettings(linear_step_mps=0.6))
    assert (info.value.name, str(info.value)) == (
        "linear_step_mps", "linear_step_mps: must not exceed max_linear_mps (0.5), got 0.6")
    with pytest.raises(SettingsError) as info:
        validate(TeleopSettings(max_angular_radps=0.2))
    assert (info.value.name, info.value.reason) == (
        "angular_step_radps", "must not exceed max_angular_radps (0.2), got 0.25")
