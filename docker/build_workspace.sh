#!/usr/bin/env bash
# Builds the workspace in the dev image: scripts/build.sh with the given arguments.
#
# gcc 12 crashed ("internal compiler error: Segmentation fault" in its strlen pass, on
# ros::Publisher::publish<sensor_msgs::JointState>) in 2 of 3 image builds on the project's
# shared 2-core machine while it was busy, on a different file each time, and never when the
# same files were compiled again (50 times) or the whole workspace was rebuilt (3 times). So
# when, and only when, the output shows an internal compiler error, the build runs once more
# (make goes on where it stopped); every other failure fails the image build at once.
set -uo pipefail
log="$(mktemp)"
scripts/build.sh "$@" 2>&1 | tee "$log"
status=${PIPESTATUS[0]}
if [ "$status" -ne 0 ] && grep -q "internal compiler error" "$log"; then
  echo "build_workspace.sh: gcc crashed (internal compiler error, above); building once more"
  scripts/build.sh "$@"
  status=$?
fi
rm -f "$log"
exit "$status"
