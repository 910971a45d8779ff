#!/usr/bin/env python3
"""Counts the JUnit XML results under a folder (gtest, rostest, pytest), lists every failure with
the last lines of its message (a CI log that keeps only the tail then still says why), and prints
one closing line "N passed, N failed, N skipped". Exit status 1 on any failure or when no test ran
at all."""
import glob
import os
import sys
import xml.etree.ElementTree as ET

MESSAGE_LINES = 12  # of each failure's text, from its end (where a traceback names the assertion)


def failure_text(element):
    """The last MESSAGE_LINES lines of a <failure>/<error>: its text, else its message attribute."""
    text = (element.text or "").strip() or (element.get("message") or "").strip()
    lines = [line for line in text.splitlines() if line.strip()]
    return lines[-MESSAGE_LINES:]


def main(folder):
    passed = failed = skipped = 0
    failures = []
    files = sorted(glob.glob(os.path.join(folder, "**", "*.xml"), recursive=True))
    for path in files:
        try:
            root = ET.parse(path).getroot()
        except ET.ParseError as e:
            failures.append((f"{path}: unreadable result file ({e})", []))
            failed += 1
            continue
        for case in root.iter("testcase"):
            name = f"{case.get('classname', '')}.{case.get('name', '')}"
            problem = case.find("failure")
            if problem is None:
                problem = case.find("error")
            if problem is not None:
                failed += 1
                failures.append((f"{os.path.relpath(path, folder)}: {name}", failure_text(problem)))
            elif case.find("skipped") is not None:
                skipped += 1
            else:
                passed += 1
    for what, lines in failures:  # why each failed first: the list and the count stay the last lines
        if lines:
            print(f"\n--- {what}")
            for line in lines:
                print(f"    {line}")
    print(f"\nTest result files: {len(files)} in {folder}")
    for what, _ in failures:
        print(f"FAILED {what}")
    print(f"{passed} passed, {failed} failed, {skipped} skipped")
    return 1 if failed or passed == 0 else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1] if len(sys.argv) > 1 else "build/test_results"))
