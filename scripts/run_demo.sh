#!/usr/bin/env bash
# The main job on a fresh Debian 12 machine: install what is missing, build, then let Conde drive
# two laps of the competition track on its own (headless, faster than real time) and print lap
# times and lane keeping. Results (path plot, rosbag, log, summary) go to results/.
set -euo pipefail
cd "$(dirname "$0")/.."
export PATH="/usr/bin:$PATH"
scripts/install_dependencies.sh build
scripts/build.sh
scripts/main_job.sh "$@"
