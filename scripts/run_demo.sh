#!/usr/bin/env bash
# The main job on a fresh Debian 12 machine: install what is missing, build, then run the whole
# competition (D1 D2 D3 D4 P1 P2 B1 B2 V1) with Conde, headless in lock-step, each challenge
# scored by the referee; prints the table and writes the reports, path plots and a summary page
# (summary.md, summary.html) to results/competition/. Options (checked before installing):
#   --challenge D3[,P1] (repeatable)  --engine bullet  --robot major_alvega  --track-seed N  --rviz
#   --output-dir DIR   (--robot major_alvega: Major Alvega through conde_major's adapter; D1 and D2 by default)
#   --profile (also the CPU time per challenge, phase and node)
# scripts/main_job.sh (the Docker run stage's command) is the two-lap run with lap times.
set -euo pipefail
cd "$(dirname "$0")/.."
export PATH="/usr/bin:$PATH"
PYTHONPATH="$PWD/src/conde_tournament/src${PYTHONPATH:+:$PYTHONPATH}" \
  /usr/bin/python3 -m conde_tournament.competition --check "$@"
scripts/install_dependencies.sh build
scripts/build.sh
set +u
# shellcheck disable=SC1091
source devel/setup.bash
set -u
rosrun conde_tournament competition "$@"
