"""Files that appear whole.  Pure Python, no ROS.

A process that watches for a file (the tournament's job runner for the referee's report and plot)
reads it as soon as it exists: the writer builds it under a temporary name in the same folder and
renames it into place, which the file system does in one step.
"""

import contextlib
import os


@contextlib.contextmanager
def replaced_whole(path):
    """Yields a temporary path beside `path` to write to (a hidden name that ends like `path`, so a
    writer that goes by the extension still can); when the block ends without an exception the
    temporary file replaces `path` in one step (os.replace), else it is removed and `path` is left
    as it was."""
    folder, name = os.path.split(os.path.abspath(path))
    tmp = os.path.join(folder, ".tmp-%d-%s" % (os.getpid(), name))
    try:
        yield tmp
        os.replace(tmp, path)
    finally:
        if os.path.exists(tmp):
            os.remove(tmp)
