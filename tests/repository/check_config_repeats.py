#!/usr/bin/env python3
"""Fails when two shipped configs repeat a section: the same WINDOW (4) consecutive lines in two
files of configs/ or configs/parts/, a line compared without its comment and its indentation,
comment lines and blank lines skipped. A config that repeats another's section starts from it instead
(`base: FILE`, see configs/README.md) and holds only what differs.

Usage: check_config_repeats.py SOURCE_DIR
"""
import glob
import os
import re
import sys

WINDOW = 4
# The laser front-end's configs are being reworked by their owner; they join the check after.
EXEMPT = re.compile(r"^laser2d_")


def lines(path):
    """(line number, text) of each line that says something: comments and indentation dropped."""
    out = []
    with open(path, encoding="utf-8") as f:
        for number, raw in enumerate(f, 1):
            text = re.sub(r"(^|\s)#.*$", "", raw).strip()
            if text:
                out.append((number, text))
    return out


def main():
    source = sys.argv[1]
    first_seen = {}  # window -> (file, line)
    repeats = []
    paths = sorted(glob.glob(os.path.join(source, "configs", "*.yaml")) +
                   glob.glob(os.path.join(source, "configs", "parts", "*.yaml")))
    for path in paths:
        name = os.path.relpath(path, os.path.join(source, "configs"))
        if EXEMPT.match(name):
            continue
        body = lines(path)
        reported_until = -1
        for i in range(len(body) - WINDOW + 1):
            window = tuple(text for _, text in body[i:i + WINDOW])
            seen = first_seen.get(window)
            if seen is None:
                first_seen[window] = (name, body[i][0])
            elif seen[0] != name and i > reported_until:
                repeats.append(f"configs/{name}:{body[i][0]} repeats configs/{seen[0]}:{seen[1]}:\n"
                               + "\n".join("    " + t for t in window))
                reported_until = i + WINDOW - 1  # one report per run of repeated lines
    if repeats:
        print(f"{len(repeats)} sections of {WINDOW}+ lines repeated across shipped configs "
              "(start the variant from its base: `base: FILE`, configs/README.md):")
        print("\n".join(repeats))
        return 1
    print(f"{len(paths)} configs, no {WINDOW} lines repeated across two of them (laser2d_* exempt)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
