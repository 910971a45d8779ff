"""Makes the package's Python sources and the shared test plumbing (src/conde_testing) importable
without building the workspace."""

import os
import sys

SRC_DIR = os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "src")
TESTING_SRC_DIR = os.path.join(os.path.dirname(os.path.dirname(SRC_DIR)), "conde_testing", "src")
sys.path[:0] = [d for d in (SRC_DIR, TESTING_SRC_DIR) if d not in sys.path]
