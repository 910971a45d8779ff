#!/usr/bin/env bash
# Every test of the workspace from a clean clone: installs what is missing, builds, runs the
# C++ unit tests (gtest) and the ROS wiring tests (rostest, real roscore on loopback) through
# catkin, the Python unit tests through pytest, and ends with one line "N passed, N failed".
set -uo pipefail
cd "$(dirname "$0")/.."
export PATH="/usr/bin:$PATH"
scripts/install_dependencies.sh build || exit 1
# podman, debootstrap, chromium, hadolint for tests/test_container_images.py and test_novnc_rviz.py
# (they skip, saying why, where no container runtime can start).
scripts/install_dependencies.sh containers || echo "install_dependencies.sh containers failed: the container tests will skip"
scripts/build.sh || exit 1
# shellcheck disable=SC1091
set +u; source devel/setup.bash; set -u
results=build/test_results
rm -rf "$results"
mkdir -p "$results/pytest"

scripts/build.sh run_tests -j1 || echo "run_tests: make reported a failure (details in the results below)"

python_tests=(src/*/test urdf/test worlds/test tests)
existing=()
for d in "${python_tests[@]}"; do [ -d "$d" ] && ls "$d"/test_*.py >/dev/null 2>&1 && existing+=("$d"); done
for d in "${existing[@]}"; do
  name=$(echo "$d" | tr '/' '_')
  /usr/bin/python3 -m pytest -q -p no:cacheprovider -o python_files="test_*.py" "$d" --junit-xml="$results/pytest/$name.xml" \
    || echo "pytest: failures in $d"
done

/usr/bin/python3 tests/summarize_results.py "$results"
