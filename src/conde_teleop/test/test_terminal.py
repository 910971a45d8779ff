"""Terminal input: cutting what a terminal sends into keys (pure), and the cbreak mode on a real
pseudo-terminal (set inside the block, restored after it, also after an exception)."""

import os
import pty
import termios

import pytest

from conde_teleop.terminal import KeyboardTerminal, split_keys


@pytest.mark.parametrize("text, keys", [
    ("", []),
    ("ijk", ["i", "j", "k"]),
    ("\x1b[A", ["\x1b[A"]),
    ("i\x1b[A\x1b[Bl", ["i", "\x1b[A", "\x1b[B", "l"]),
    ("\x1bOA\x1bOD", ["\x1bOA", "\x1bOD"]),  # application cursor mode
    ("\x1b[1;5C,", ["\x1b[1;5C", ","]),  # Ctrl+Right: parameters before the final byte
    ("\x1b[15~ ", ["\x1b[15~", " "]),  # F5
    ("\x1bxq", ["\x1bx", "q"]),  # Alt+x
    ("\x1b", ["\x1b"]),  # Esc
    ("\x1b\x1b[A", ["\x1b", "\x1b[A"]),
    ("i\x1b[", ["i", "\x1b["]),  # cut off: kept as it is
    ("\x1b[1;5", ["\x1b[1;5"]),
    ("\x1bO", ["\x1bO"]),
    ("é\x03", ["é", "\x03"]),
])
def test_split_keys(text, keys):
    assert split_keys(text) == keys


@pytest.fixture
def pseudo_terminal():
    master_fd, slave_fd = pty.openpty()
    yield master_fd, slave_fd
    os.close(slave_fd)
    os.close(master_fd)


def test_cbreak_inside_and_restored_after(pseudo_terminal):
    master_fd, slave_fd = pseudo_terminal
    saved = termios.tcgetattr(slave_fd)
    assert saved[3] & termios.ICANON and saved[3] & termios.ECHO
    with KeyboardTerminal(slave_fd) as terminal:
        lflag = termios.tcgetattr(slave_fd)[3]
        assert not lflag & termios.ICANON and not lflag & termios.ECHO
        assert lflag & termios.ISIG  # Ctrl-C still raises SIGINT
        assert terminal.read_keys(0.0) == []
        os.write(master_fd, b"i\x1b[Aq")  # no Enter needed
        assert terminal.read_keys(30.0) == ["i", "\x1b[A", "q"]
        os.write(master_fd, b"\x1b")
        assert terminal.read_keys(30.0) == ["\x1b"]
    assert termios.tcgetattr(slave_fd) == saved


def test_restored_after_an_exception(pseudo_terminal):
    _, slave_fd = pseudo_terminal
    saved = termios.tcgetattr(slave_fd)
    with pytest.raises(KeyboardInterrupt):
        with KeyboardTerminal(slave_fd):
            raise KeyboardInterrupt
    assert termios.tcgetattr(slave_fd) == saved


def test_end_of_the_terminal_is_eof():
    master_fd, slave_fd = pty.openpty()
    try:
        with KeyboardTerminal(slave_fd) as terminal:
            os.close(master_fd)
            master_fd = None
            with pytest.raises(EOFError):
                terminal.read_keys(30.0)
    finally:
        os.close(slave_fd)
        if master_fd is not None:
            os.close(master_fd)
