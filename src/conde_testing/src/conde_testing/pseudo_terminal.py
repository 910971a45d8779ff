"""A real pseudo-terminal for the tests of nodes that read keys from their terminal."""

import os
import pty
import termios
import threading


class Terminal:
    """A pseudo-terminal: the node gets its slave side as stdin and stdout; the test types on the
    master side and collects what the node prints (`output`, bytes). A `with` block closes both
    sides on the way out."""

    def __init__(self):
        self.master_fd, self.slave_fd = pty.openpty()
        self.saved = termios.tcgetattr(self.slave_fd)
        self.output = b""
        self._reader = threading.Thread(target=self._read, daemon=True)
        self._reader.start()

    def _read(self):
        while True:
            try:
                data = os.read(self.master_fd, 4096)
            except OSError:
                return
            if not data:
                return
            self.output += data

    def type(self, keys):
        os.write(self.master_fd, keys)

    def in_cbreak_mode(self):
        lflag = termios.tcgetattr(self.slave_fd)[3]
        return not lflag & termios.ICANON and not lflag & termios.ECHO

    def restored(self):
        """The terminal's settings are the ones it had before the node ran."""
        return termios.tcgetattr(self.slave_fd) == self.saved

    def close(self):
        os.close(self.slave_fd)
        os.close(self.master_fd)

    def __enter__(self):
        return self

    def __exit__(self, *exc_info):
        self.close()
