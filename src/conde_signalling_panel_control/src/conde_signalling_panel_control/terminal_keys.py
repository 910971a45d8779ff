"""Single key presses from a terminal, without Enter, for the panel menu.

RawTerminal switches the terminal to cbreak mode (no line buffering, no echo; Ctrl-C still sends
SIGINT) and restores the saved settings on exit, also after an exception or KeyboardInterrupt.
"""
import os
import select
import termios
import tty

ESC = 0x1b
_ESC_SEQUENCE_WAIT_S = 0.05  # the rest of an arrow key's sequence arrives within this


def split_keys(data):
    """Splits bytes read from a terminal into keys: one character each, except that an escape
    sequence (e.g. an arrow key, ESC [ A) counts as one key. A lone ESC byte is the Esc key."""
    keys = []
    i = 0
    while i < len(data):
        if data[i] == ESC and i + 1 < len(data):
            end = i + 2
            if data[i + 1] in b"[O":  # CSI / SS3: parameters, then a final byte in 0x40..0x7e
                while end < len(data) and not 0x40 <= data[end] <= 0x7e:
                    end += 1
                end += 1
            keys.append(data[i:end].decode("utf-8", "replace"))
            i = end
        else:
            keys.append(data[i:i + 1].decode("utf-8", "replace"))
            i += 1
    return keys


def _readable(fd, timeout_s):
    return bool(select.select([fd], [], [], timeout_s)[0])


class RawTerminal:
    """Context manager: the terminal on `fd` in cbreak mode while inside."""

    def __init__(self, fd):
        self.fd = fd
        self._saved = None

    def __enter__(self):
        self._saved = termios.tcgetattr(self.fd)
        tty.setcbreak(self.fd, termios.TCSANOW)
        return self

    def __exit__(self, *exc_info):
        termios.tcsetattr(self.fd, termios.TCSADRAIN, self._saved)
        return False

    def read_keys(self, timeout_s):
        """Keys typed so far, waiting up to timeout_s [s] for the first; [] on timeout.
        Raises EOFError when the terminal is gone."""
        if not _readable(self.fd, timeout_s):
            return []
        try:
            data = os.read(self.fd, 64)
            if data == bytes([ESC]) and _readable(self.fd, _ESC_SEQUENCE_WAIT_S):
                data += os.read(self.fd, 64)
        except OSError as error:  # EIO once the other end of a pseudo-terminal is closed
            raise EOFError("terminal read failed: %s" % error.strerror) from None
        if not data:
            raise EOFError("terminal closed")
        return split_keys(data)
