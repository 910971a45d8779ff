"""The teleop keymap (conde_racing.teleop_keys): keys, steps, limits, arrow-key sequences."""

import pytest

from conde_racing.teleop_keys import DriveCommand, TeleopLimits, apply_key, split_keys, status_line

LIMITS = TeleopLimits(speed_step_mps=0.25, steering_step_rad=0.05, max_speed_mps=1.0, max_reverse_speed_mps=0.5,
                      max_steering_rad=0.12)


def press(keys, command=DriveCommand()):
    for key in split_keys(keys):
        command = apply_key(key, command, LIMITS)
        if command is None:
            return None
    return command


@pytest.mark.parametrize("keys, speed, steering", [
    ("w", 0.25, 0.0), ("\x1b[A", 0.25, 0.0), ("ww", 0.5, 0.0),
    ("s", -0.25, 0.0), ("\x1b[B", -0.25, 0.0),
    ("a", 0.0, 0.05), ("\x1b[D", 0.0, 0.05), ("d", 0.0, -0.05), ("\x1b[C", 0.0, -0.05),
    ("W", 0.25, 0.0), ("\x1bOA", 0.25, 0.0),          # capitals; arrows in application mode
])
def test_each_key(keys, speed, steering):
    assert press(keys) == DriveCommand(speed, steering)


def test_limits_hold():
    assert press("w" * 10) == DriveCommand(1.0, 0.0)
    assert press("s" * 10) == DriveCommand(-0.5, 0.0)
    assert press("a" * 10) == DriveCommand(0.0, 0.12)
    assert press("d" * 10) == DriveCommand(0.0, -0.12)


def test_stop_centre_and_unknown_keys():
    moving = press("wwwaa")
    assert moving == DriveCommand(0.75, 0.1)
    assert press(" ", moving) == DriveCommand(0.0, 0.1)      # stop keeps the steering
    assert press("c", moving) == DriveCommand(0.75, 0.0)
    assert press("xyz1\t", moving) == moving


def test_quit():
    assert press("wq") is None
    assert press("\x03") is None


def test_steps_do_not_accumulate_float_error():
    assert press("w" * 3 + "s" * 3) == DriveCommand(0.0, 0.0)
    limits = TeleopLimits(speed_step_mps=0.1)
    command = DriveCommand()
    for _ in range(3):
        command = apply_key("w", command, limits)
    assert command.speed_mps == 0.3


def test_split_keys():
    assert split_keys("a\x1b[Cb\x1b[A") == ["a", "\x1b[C", "b", "\x1b[A"]
    assert split_keys("\x1b") == ["\x1b"]                    # a lone Escape stays a key (ignored)


@pytest.mark.parametrize("field", ["speed_step_mps", "max_speed_mps", "max_steering_rad"])
def test_bad_limits(field):
    with pytest.raises(ValueError, match=field):
        TeleopLimits(**{field: 0.0})


def test_status_line():
    assert status_line(DriveCommand(0.5, -0.1)) == "speed +0.50 m/s  steering -0.100 rad"
