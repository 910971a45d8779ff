#!/usr/bin/env bash
# The main job in a workspace that is already built (or installed): sources the workspace and
# runs the headless autonomous run, printing its result. scripts/run_demo.sh installs and builds first;
# the Docker run stage calls this directly. Extra arguments go to the job.
set -euo pipefail
cd "$(dirname "$0")/.."
export PATH="/usr/bin:$PATH"
SETUP="${CONDE_SETUP:-devel/setup.bash}"
set +u
# shellcheck disable=SC1090
source "$SETUP"
set -u
OUTPUT_DIR="${CONDE_RESULTS_DIR:-$PWD/results}"
# Conde drives two laps on its own (ODE; --engine bullet for the other engine); exit 0 on pass.
rosrun conde_eval autonomous_run --output-dir "$OUTPUT_DIR" "$@"
