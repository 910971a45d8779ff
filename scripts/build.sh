#!/usr/bin/env bash
# Builds the workspace in place: the repository root is the catkin source space; build/ and
# devel/ are created next to src/ (both git-ignored). Extra arguments go to catkin_make.
#
# A compiler that crashes (gcc's "internal compiler error", or cc1plus killed) says nothing about
# the code: such a build is run once more, with one job, before it counts as failed. Any other
# build error fails at once.
set -euo pipefail
cd "$(dirname "$0")/.."
export PATH="/usr/bin:$PATH"   # ROS Python lives with /usr/bin/python3, not with other pythons
log=$(mktemp "${TMPDIR:-/tmp}/conde_build.XXXXXX")
trap 'rm -f "$log"' EXIT
build() {
  catkin_make --source . --build build -DPYTHON_EXECUTABLE=/usr/bin/python3 -DCMAKE_BUILD_TYPE=RelWithDebInfo "$@" 2>&1 | tee "$log"
  return "${PIPESTATUS[0]}"
}
status=0
build -j"$(nproc)" "$@" || status=$?
if [ "$status" -ne 0 ] && grep -q -e "internal compiler error" -e "Killed signal terminated program" "$log"; then
  echo "build.sh: the compiler crashed (not an error in the code); building once more with one job" >&2
  status=0
  build "$@" -j1 || status=$?
fi
exit "$status"
