#!/usr/bin/env python3
"""Counts the JUnit XML results under a folder (gtest, rostest, pytest), lists every failure,
and prints one closing line "N passed, N failed, N skipped". Exit status 1 on any failure or
when no test ran at all."""
import glob
import os
import sys
import xml.etree.ElementTree as ET


def main(folder):
    passed = failed = skipped = 0
    failures = []
    files = sorted(glob.glob(os.path.join(folder, "**", "*.xml"), recursive=True))
    for path in files:
        try:
            root = ET.parse(path).getroot()
        except ET.ParseError as e:
            failures.append(f"{path}: unreadable result file ({e})")
            failed += 1
            continue
        for case in root.iter("testcase"):
            name = f"{case.get('classname', '')}.{case.get('name', '')}"
            if case.find("failure") is not None or case.find("error") is not None:
                failed += 1
                failures.append(f"{os.path.relpath(path, folder)}: {name}")
            elif case.find("skipped") is not None:
                skipped += 1
            else:
                passed += 1
    print(f"\nTest result files: {len(files)} in {folder}")
    for f in failures:
        print(f"FAILED {f}")
    print(f"{passed} passed, {failed} failed, {skipped} skipped")
    return 1 if failed or passed == 0 else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1] if len(sys.argv) > 1 else "build/test_results"))
