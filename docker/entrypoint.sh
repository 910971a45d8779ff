#!/usr/bin/env bash
# Entry point of the conde_sim images: sources the workspace named by CONDE_SETUP (the install
# space in run/gui, the devel space in dev; skipped while it does not exist yet) and runs the
# command, e.g. `docker run --rm conde_sim:run rosrun conde_eval odometry_test --engines ode`.
set -e
export PATH="/usr/bin:$PATH"
command=("$@")
set --  # catkin's setup.bash reads the positional parameters as its own options
if [ -n "${CONDE_SETUP:-}" ] && [ -f "$CONDE_SETUP" ]; then
  # shellcheck disable=SC1090
  source "$CONDE_SETUP"
fi
exec "${command[@]}"
