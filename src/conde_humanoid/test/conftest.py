"""Makes the shared test plumbing (src/conde_testing) importable without building the workspace."""

import os
import sys

TESTING_SRC_DIR = os.path.join(os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__)))),
                               "conde_testing", "src")
if TESTING_SRC_DIR not in sys.path:
    sys.path.insert(0, TESTING_SRC_DIR)
