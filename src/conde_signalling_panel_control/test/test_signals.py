"""Signal names and codes, the menu keys, and splitting terminal input into keys."""
import pytest

from conde_signalling_panel_control import signals
from conde_signalling_panel_control.terminal_keys import split_keys


def test_codes_equal_the_panel_signal_message_constants():
    try:
        from conde_msgs.msg import PanelSignal
    except ImportError:
        pytest.fail("conde_msgs is not importable: build the workspace and source devel/setup.bash")
    for name, code in signals.SIGNAL_CODES.items():
        assert getattr(PanelSignal, name.upper()) == code, name
    constants = {k for k in vars(PanelSignal) if k.isupper() and isinstance(getattr(PanelSignal, k), int)}
    assert constants == {name.upper() for name in signals.SIGNAL_NAMES}


def test_names_and_codes_round_trip():
    assert signals.SIGNAL_NAMES == ("none", "left", "right", "forward", "stop", "end_of_trial", "parking")
    for name in signals.SIGNAL_NAMES:
        assert signals.name_of(signals.code_of(name)) == name


def test_unknown_name_and_code():
    with pytest.raises(ValueError) as error:
        signals.code_of("stp")
    assert str(error.value) == ("unknown signal 'stp' (expected one of: none, left, right, forward, stop, "
                                "end_of_trial, parking)")
    with pytest.raises(ValueError) as error:
        signals.name_of(7)
    assert str(error.value) == "unknown signal code 7 (expected 0..6)"


def test_menu_keys_are_the_original_ones_plus_end_of_trial_and_none():
    assert signals.MENU_KEYS == {"0": "left", "1": "right", "2": "forward", "3": "stop", "4": "parking",
                                 "5": "end_of_trial", "n": "none"}
    assert set(signals.MENU_KEYS.values()) == set(signals.SIGNAL_NAMES)


def test_menu_text_lists_every_key_and_the_current_signal():
    text = signals.menu_text("stop")
    lines = text.splitlines()
    assert lines[0] == "Choose the semaphore [Press <Esc> to exit]"
    for key, name in signals.MENU_KEYS.items():
        assert any(line.split()[:2] == [key, name] for line in lines), key
    assert lines[-1] == "Current signal: stop"


def test_split_keys():
    assert split_keys(b"03n") == ["0", "3", "n"]
    assert split_keys(b"\x1b") == ["\x1b"]
    # Arrow keys (CSI and SS3 forms) and F5 are one key each, not Esc.
    assert split_keys(b"\x1b[A1\x1bOB\x1b[15~") == ["\x1b[A", "1", "\x1bOB", "\x1b[15~"]
    assert split_keys(b"") == []
