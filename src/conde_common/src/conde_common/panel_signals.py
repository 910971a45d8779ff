"""The signalling panel's signals: names and codes, taken from the constants of conde_msgs/PanelSignal
(NONE = 0 ... PARKING = 6; the name of a constant in lower case is the signal's name)."""
from collections import OrderedDict

from conde_msgs.msg import PanelSignal

#: name -> code, in code order: none, left, right, forward, stop, end_of_trial, parking
SIGNAL_CODES = OrderedDict(sorted(
    ((name.lower(), getattr(PanelSignal, name)) for name in dir(PanelSignal)
     if name.isupper() and isinstance(getattr(PanelSignal, name), int)),
    key=lambda item: item[1]))
SIGNAL_NAMES = tuple(SIGNAL_CODES)
#: code -> name
NAMES_BY_CODE = {code: name for name, code in SIGNAL_CODES.items()}
