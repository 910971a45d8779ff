#!/usr/bin/env bash
# Every test of the workspace from a clean clone: installs what is missing, builds, runs the
# linters, then through catkin (catkin_make run_tests) the C++ unit tests (gtest), the ROS wiring tests
# (rostest, real roscore on loopback) and every package's Python tests (pytest), and ends with one
# line "N passed, N failed, N skipped".
#
# usage: tests/run_all_tests.sh [--unit]
#   --unit (or CONDE_TEST_TIER=unit): the unit tier only: the gtests and the pure-Python pytest
#          files (no ROS master, no simulator run): every test_*.py under src/*/test, urdf/test and
#          worlds/test except the node tests (files named test_*node*.py); tests/ (system tests,
#          container tests) and the rostests are left out. The Docker dev image is checked with it.
set -uo pipefail
cd "$(dirname "$0")/.." || exit 1
export PATH="/usr/bin:$PATH"

tier="${CONDE_TEST_TIER:-all}"
case "${1:-}" in
  --unit) tier=unit ;;
  "") ;;
  *) echo "run_all_tests.sh: unknown option '$1' (usage: tests/run_all_tests.sh [--unit])" >&2; exit 2 ;;
esac
case "$tier" in
  all|unit) ;;
  *) echo "run_all_tests.sh: CONDE_TEST_TIER='$tier' (expected all or unit)" >&2; exit 2 ;;
esac

scripts/install_dependencies.sh build || exit 1
if [ "$tier" = all ]; then
  # podman, debootstrap, chromium, hadolint for tests/test_container_images.py and test_novnc_rviz.py
  # (they skip, saying why, where no container runtime can start).
  scripts/install_dependencies.sh containers || echo "install_dependencies.sh containers failed: the container tests will skip"
  # Ray (pinned, in its own virtualenv) for the tournament test's Ray cluster (tests/test_tournament.py).
  scripts/install_dependencies.sh tournament || echo "install_dependencies.sh tournament failed: the tournament test's Ray part will fail"
fi
scripts/build.sh || exit 1
set +u
# shellcheck disable=SC1091
source devel/setup.bash
set -u
results=build/test_results
rm -rf "$results"
mkdir -p "$results/pytest"

# The linters first (clang-format, flake8, catkin_lint, shellcheck; on the files of the git
# checkout): a finding fails the run.
if [ "$tier" = all ]; then
  scripts/lint.sh "$results/lint" || echo "lint: findings (listed above)"
fi

# The targets run_tests_<package>_<type> that catkin made in build/ (one per package and type of
# test) for the types given as a sed alternation, e.g. 'gtest' or 'gtest\|pytest'.
test_targets_of() {
  make -C build help | sed -n "s/^\.\.\. \(run_tests_[A-Za-z0-9_]*_\($1\)\)\$/\1/p"
}

if [ "$tier" = unit ]; then
  mapfile -t gtest_targets < <(test_targets_of 'gtest')
  [ "${#gtest_targets[@]}" -gt 0 ] || { echo "run_all_tests.sh: no run_tests_<package>_gtest target in build/" >&2; exit 1; }
  scripts/build.sh "${gtest_targets[@]}" -j1 || echo "gtest: make reported a failure (details in the results below)"
  for d in src/*/test urdf/test worlds/test; do
    ls "$d"/test_*.py >/dev/null 2>&1 || continue
    /usr/bin/python3 -m pytest -q -p no:cacheprovider -o python_files="test_*.py" --ignore-glob="*/test_*node*.py" "$d" \
      --junit-xml="$results/pytest/$(echo "$d" | tr '/' '_').xml" || echo "pytest: failures in $d"
  done
else
  # The container tests (tests/test_container_images.py, test_novnc_rviz.py: about 18 min, most of
  # it podman building the images and running the main job and the unit tier in them) run in a
  # pytest of their own beside the catkin run below, at a lower CPU priority (their image builds at
  # the lowest), so they take the CPU that the simulation runs in lock-step leave idle; the catkin
  # run leaves them out (CONDE_CONTAINER_TESTS=apart, tests/conftest.py). Their output:
  # build/test_results/containers/pytest.log.
  mkdir -p "$results/containers"
  containers_xml="$results/containers/pytest-containers.xml"
  BUILD_NICENESS=19 nice -n 10 /usr/bin/python3 -m pytest -q -p no:cacheprovider -o python_files="test_*.py" \
    tests/test_container_images.py tests/test_novnc_rviz.py --junit-xml="$containers_xml" \
    > "$results/containers/pytest.log" 2>&1 &
  containers_pid=$!
  # The test executables first, on every core (the test targets below would compile them one at
  # a time).
  scripts/build.sh tests || echo "tests: the build failed (run_tests below names what is missing)"
  # Every test registered with catkin: gtest, rostest, and each package's pytest files
  # (conde_add_pytests of conde_testing), with their results under build/test_results/<package>,
  # in two streams side by side, because a simulation in lock-step keeps about one core busy and
  # one test at a time left the other core idle: the system tests of tests/ (about half of the
  # run; their output goes to build/test_results/system_tests.log and is printed when they end)
  # and every other package's tests and the rostests, one target at a time. Each rostest and each
  # test's roscore has a free port of its own, and the tests step the simulation, so they do not
  # need the machine to themselves. The per-package targets run_tests_<package>_<type> are used
  # (make's run_tests would run them one at a time and clean the results first: done above).
  mapfile -t test_targets < <(test_targets_of 'gtest\|rostest\|pytest\|nosetests')
  system_target=run_tests_conde_tests_pytest
  other_targets=()
  for target in "${test_targets[@]}"; do
    [ "$target" = "$system_target" ] || other_targets+=("$target")
  done
  if [ "${#other_targets[@]}" -eq "${#test_targets[@]}" ] || [ "${#other_targets[@]}" -eq 0 ]; then
    echo "run_all_tests.sh: expected $system_target and other run_tests_<package>_<type> targets in build/, found: ${test_targets[*]}" >&2
    exit 1
  fi
  CONDE_CONTAINER_TESTS=apart make -C build "$system_target" > "$results/system_tests.log" 2>&1 &
  system_pid=$!
  make -C build -j1 "${other_targets[@]}" || echo "run_tests: make reported a failure (details in the results below)"
  echo "run_all_tests.sh: waiting for the system tests of tests/ (pid $system_pid)"
  wait "$system_pid" || echo "run_tests: make reported a failure in the system tests (details in the results below)"
  cat "$results/system_tests.log"
  echo "run_all_tests.sh: waiting for the container tests (pid $containers_pid)"
  wait "$containers_pid"
  containers_status=$?
  tail -n 25 "$results/containers/pytest.log"
  if [ ! -s "$containers_xml" ]; then  # pytest died before writing its results: a failure, not a silence
    echo "run_all_tests.sh: the container tests exited $containers_status without results (see $results/containers/pytest.log)"
    printf '<testsuite name="containers"><testcase classname="containers" name="pytest"><failure message="exit %s, no results"/></testcase></testsuite>\n' \
      "$containers_status" > "$containers_xml"
  fi
  # A folder of Python tests that no package registered would be skipped without a word: fail instead.
  for d in src/*/test urdf/test worlds/test tests; do
    ls "$d"/test_*.py >/dev/null 2>&1 || continue
    package=$(sed -n 's:.*<name>\(.*\)</name>.*:\1:p' "$(dirname "$d")/package.xml" "$d/package.xml" 2>/dev/null | head -n 1)
    if ! ls "$results/$package"/pytest-*.xml >/dev/null 2>&1; then
      echo "run_all_tests.sh: $d has Python tests but package $package produced no pytest results (conde_add_pytests?)"
      printf '<testsuite name="registration"><testcase classname="registration" name="%s"><failure message="not registered"/></testcase></testsuite>\n' \
        "$d" > "$results/pytest/unregistered_$(echo "$d" | tr '/' '_').xml"
    fi
  done
fi

/usr/bin/python3 tests/summarize_results.py "$results"
