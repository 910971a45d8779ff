#!/usr/bin/env bash
# The workspace's linters, on the files git tracks (and new files it does not ignore):
#   clang-format  C and C++ (.clang-format: Google style, 120 columns), as a check, no rewrite
#   flake8        Python modules, tests and the scripts whose first line names python (.flake8)
#   catkin_lint   every package (errors and warnings)
#   and shell scripts through shellcheck (*.sh and the scripts whose first line names bash or sh)
# Prints each finding, writes one JUnit test case per linter to RESULTS_DIR/lint.xml when given,
# and exits 1 when any linter found something.
#
# usage: scripts/lint.sh [RESULTS_DIR]
#   scripts/lint.sh --fix-format    rewrites the C/C++ files with clang-format instead
set -uo pipefail
cd "$(dirname "$0")/.." || exit 1
export PATH="/usr/bin:$PATH"

mapfile -t tracked < <(git ls-files --cached --others --exclude-standard)
cpp_files=() python_files=() shell_files=()
for f in "${tracked[@]}"; do
  [ -f "$f" ] || continue
  case "$f" in
    *.cpp | *.h | *.hpp | *.c) cpp_files+=("$f") ;;
    *.py) python_files+=("$f") ;;
    *.sh) shell_files+=("$f") ;;
    *.*) ;;
    *)
      first=$(head -c 100 "$f" 2>/dev/null | head -n 1)
      case "$first" in
        "#!"*python*) python_files+=("$f") ;;
        "#!"*bash* | "#!"*/sh) shell_files+=("$f") ;;
      esac ;;
  esac
done

if [ "${1:-}" = --fix-format ]; then
  clang-format -i "${cpp_files[@]}"
  exit 0
fi
results_dir="${1:-}"

names=() outputs=() statuses=()
run_linter() {  # name, command...
  local name=$1 output status
  shift
  output=$("$@" 2>&1)
  status=$?
  names+=("$name") outputs+=("$output") statuses+=("$status")
  if [ "$status" -eq 0 ]; then
    echo "lint: $name: clean"
  else
    echo "lint: $name: findings (exit $status):"
    printf '%s\n' "$output" | sed 's/^/  /'
  fi
}

run_linter clang-format clang-format --dry-run -Werror "${cpp_files[@]}"
run_linter flake8 flake8 "${python_files[@]}"
run_linter catkin_lint catkin_lint -W1 --strict --quiet .
run_linter shellcheck shellcheck "${shell_files[@]}"

failed=0
for s in "${statuses[@]}"; do [ "$s" -eq 0 ] || failed=1; done

if [ -n "$results_dir" ]; then
  mkdir -p "$results_dir"
  /usr/bin/python3 - "$results_dir/lint.xml" "${#names[@]}" "${names[@]}" "${statuses[@]}" "${outputs[@]}" <<'PY'
import sys
import xml.etree.ElementTree as ET

path, count = sys.argv[1], int(sys.argv[2])
rest = sys.argv[3:]
names, statuses, outputs = rest[:count], rest[count:2 * count], rest[2 * count:3 * count]
suite = ET.Element("testsuite", name="lint", tests=str(count),
                   failures=str(sum(1 for s in statuses if s != "0")))
for name, status, output in zip(names, statuses, outputs):
    case = ET.SubElement(suite, "testcase", classname="lint", name=name)
    if status != "0":
        failure = ET.SubElement(case, "failure", message=f"{name} found problems (exit {status})")
        failure.text = output
ET.ElementTree(suite).write(path, encoding="unicode")
PY
fi
exit "$failed"
