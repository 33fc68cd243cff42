#!/usr/bin/env python3
"""Prints how many tests a ctest run skipped and why, from its JUnit file (ctest --output-junit).

ctest counts a skipped test as passed ("100% tests passed") and --output-on-failure shows no
reason; GoogleTest writes the reason (GTEST_SKIP() << "...") into the test's output, which the
JUnit file keeps. Usage: skipped_tests.py JUNIT.xml   (prints nothing when no test skipped)
"""
import re
import sys
import xml.etree.ElementTree as ET


def reason(case):
    out = case.findtext("system-out") or ""
    # GoogleTest: "file:line: Skipped\n<message>\n[  SKIPPED ] Suite.Name"
    m = re.search(r": Skipped\n(.*?)\n\[  SKIPPED \]", out, re.S)
    if m and m.group(1).strip():
        return " ".join(m.group(1).split())
    skipped = case.find("skipped")
    if skipped is not None and skipped.get("message"):
        return skipped.get("message")
    return "no reason given"


def main(path):
    try:
        cases = ET.parse(path).getroot().iter("testcase")
    except (OSError, ET.ParseError) as e:
        print(f"skipped tests: cannot read {path}: {e}", file=sys.stderr)
        return 1
    by_reason = {}
    for case in cases:
        if case.get("status") in ("notrun", "skipped", "disabled") or case.find("skipped") is not None:
            by_reason.setdefault(reason(case), []).append(case.get("name", "?"))
    total = sum(len(v) for v in by_reason.values())
    if total == 0:
        return 0
    print(f"\n{total} test{'s' if total != 1 else ''} skipped (ctest counts them as passed):")
    for why, names in sorted(by_reason.items(), key=lambda kv: (-len(kv[1]), kv[0])):
        shown = ", ".join(names[:3]) + (f" and {len(names) - 3} more" if len(names) > 3 else "")
        print(f"  {len(names):3d} x {why}\n        {shown}")
    return 0


if __name__ == "__main__":
    if len(sys.argv) != 2:
        print(__doc__.strip(), file=sys.stderr)
        sys.exit(2)
    sys.exit(main(sys.argv[1]))
