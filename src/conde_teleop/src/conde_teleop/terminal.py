"""Single key presses from a terminal, without Enter.

split_keys() (pure) cuts what a terminal sent into keys.  KeyboardTerminal puts the terminal into
cbreak mode: input is not line-buffered and not echoed, but output processing and the signal
characters stay on.  That is deliberate (rather than full raw mode): Ctrl-C still raises SIGINT
for whoever owns the terminal (this node, or roslaunch when the node runs under it), and log lines
written to the same terminal still start at the left margin.  The saved settings are put back when
the `with` block ends, whichever way it ends.
"""

import os
import select
import termios
import tty
from typing import List

ESC = "\x1b"
_REST_OF_SEQUENCE_S = 0.05  # [s] the bytes after an ESC of an arrow key arrive within this


def split_keys(text: str) -> List[str]:
    """Splits text read from a terminal into keys: one character each, except that an escape
    sequence is one key: ESC [ parameters final-byte (CSI, e.g. Up = ESC [ A), ESC O x (SS3,
    e.g. Up in application cursor mode) and ESC x (Alt+x).  An ESC followed by another ESC or at
    the end is the Esc key; a sequence cut off at the end of the text is returned as it is."""
    keys = []
    i = 0
    while i < len(text):
        end = i + 1
        if text[i] == ESC and end < len(text) and text[end] != ESC:
            end += 1
            if text[i + 1] == "[":
                while end < len(text) and not "\x40" <= text[end] <= "\x7e":  # parameter/intermediate bytes
                    end += 1
                end = min(end + 1, len(text))  # the final byte
            elif text[i + 1] == "O":
                end = min(end + 1, len(text))
        keys.append(text[i:end])
        i = end
    return keys


def _readable(fd: int, timeout_s: float) -> bool:
    return bool(select.select([fd], [], [], timeout_s)[0])


class KeyboardTerminal:
    """Context manager: the terminal on file descriptor `fd` in cbreak mode while inside."""

    def __init__(self, fd: int):
        self.fd = fd
        self._saved = None

    def __enter__(self) -> "KeyboardTerminal":
        self._saved = termios.tcgetattr(self.fd)
        try:
            tty.setcbreak(self.fd, termios.TCSANOW)
        except BaseException:
            termios.tcsetattr(self.fd, termios.TCSANOW, self._saved)
            raise
        return self

    def __exit__(self, *exc_info) -> bool:
        try:
            termios.tcsetattr(self.fd, termios.TCSADRAIN, self._saved)
        except termios.error:
            pass  # the terminal is gone (e.g. its window was closed): nothing left to restore
        return False

    def read_keys(self, timeout_s: float) -> List[str]:
        """The keys typed so far, waiting up to timeout_s [s] for the first; [] on timeout.
        Raises EOFError when the terminal has gone away."""
        if not _readable(self.fd, timeout_s):
            return []
        try:
            data = os.read(self.fd, 256)
            if data.endswith(ESC.encode()) and _readable(self.fd, _REST_OF_SEQUENCE_S):
                data += os.read(self.fd, 256)
        except OSError as error:  # EIO once the other side of a pseudo-terminal is closed
            raise EOFError("reading the terminal failed: %s" % error.strerror) from None
        if not data:
            raise EOFError("the terminal was closed")
        return split_keys(data.decode("utf-8", "replace"))
