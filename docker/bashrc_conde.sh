# shellcheck shell=bash
# Sourced by ~/.bashrc in the dev image and the dev container: ROS Python comes with
# /usr/bin/python3, and the workspace's devel space once it has been built (scripts/build.sh).
export PATH="/usr/bin:$PATH"
if [ -f "${CONDE_SETUP:-}" ]; then
  # shellcheck disable=SC1090
  source "$CONDE_SETUP"
fi
