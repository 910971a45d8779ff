"""Signal names, their conde_msgs/PanelSignal codes (from conde_common.panel_signals, which takes
them from the message), and the keys of the terminal menu."""
from collections import OrderedDict

from conde_common.panel_signals import NAMES_BY_CODE as _NAMES_BY_CODE
from conde_common.panel_signals import SIGNAL_CODES, SIGNAL_NAMES  # noqa: F401 (re-exported)

# What each signal asks of the robot, for the menu.
SIGNAL_MEANINGS = {
    "none": "black screen",
    "left": "turn left",
    "right": "turn right",
    "forward": "go forward",
    "stop": "stop",
    "end_of_trial": "end of trial (checkerboard)",
    "parking": "go to parking",
}

# Menu keys: 0-4 as in the original controller; 5 and n are additions.
MENU_KEYS = OrderedDict([
    ("0", "left"),
    ("1", "right"),
    ("2", "forward"),
    ("3", "stop"),
    ("4", "parking"),
    ("5", "end_of_trial"),
    ("n", "none"),
])
ESC_KEY = "\x1b"
MENU_TITLE = "Choose the semaphore [Press <Esc> to exit]"


def unknown_signal_message(value):
    """The error text for a name that is not a signal, listing the valid names."""
    return "unknown signal %r (expected one of: %s)" % (value, ", ".join(SIGNAL_NAMES))


def code_of(name):
    """PanelSignal code of a signal name; ValueError naming the valid names otherwise."""
    if not isinstance(name, str) or name not in SIGNAL_CODES:
        raise ValueError(unknown_signal_message(name))
    return SIGNAL_CODES[name]


def name_of(code):
    """Signal name of a PanelSignal code; ValueError for a code outside 0..6."""
    if code not in _NAMES_BY_CODE:
        raise ValueError("unknown signal code %r (expected %d..%d)"
                         % (code, min(_NAMES_BY_CODE), max(_NAMES_BY_CODE)))
    return _NAMES_BY_CODE[code]


def menu_text(current_signal):
    """The terminal menu: title, one line per key, and the signal now shown."""
    lines = [MENU_TITLE, ""]
    for key, name in MENU_KEYS.items():
        lines.append("  %s  %-13s %s" % (key, name, SIGNAL_MEANINGS[name]))
    lines.append("  Esc exits; any other key publishes the current picture again")
    lines.append("")
    lines.append("Current signal: %s" % current_signal)
    return "\n".join(lines)
