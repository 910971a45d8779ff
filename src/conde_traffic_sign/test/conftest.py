"""Makes the package's Python sources and conde_worlds (the sign drawings) importable without
building the workspace."""

import os
import sys

PKG_DIR = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SRC_DIR = os.path.join(PKG_DIR, "src")
WORLDS_SRC_DIR = os.path.join(os.path.dirname(os.path.dirname(PKG_DIR)), "worlds", "src")
sys.path[:0] = [d for d in (SRC_DIR, WORLDS_SRC_DIR) if d not in sys.path]
