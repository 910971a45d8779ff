#!/usr/bin/env bash
# Builds the workspace in place: the repository root is the catkin source space; build/ and
# devel/ are created next to src/ (both git-ignored). Extra arguments go to catkin_make.
set -euo pipefail
cd "$(dirname "$0")/.."
export PATH="/usr/bin:$PATH"   # ROS Python lives with /usr/bin/python3, not with other pythons
catkin_make --source . --build build -DPYTHON_EXECUTABLE=/usr/bin/python3 -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -j"$(nproc)" "$@"
