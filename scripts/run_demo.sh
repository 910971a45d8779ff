#!/usr/bin/env bash
# The main job on a fresh Debian 12 machine: install what is missing, build, then run the
# odometry test of Conde on the competition track on both physics engines (headless, faster than
# real time) and print its table. Results go to results/.
set -euo pipefail
cd "$(dirname "$0")/.."
export PATH="/usr/bin:$PATH"
scripts/install_dependencies.sh build
scripts/build.sh
scripts/main_job.sh "$@"
