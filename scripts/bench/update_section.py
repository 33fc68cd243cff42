#!/usr/bin/env python3
"""Replaces the text between <!-- NAME:begin --> and <!-- NAME:end --> in docs/benchmarks.md
(appending the section when absent) with standard input. Other sections are left untouched."""
import pathlib
import sys

name, path = sys.argv[1], pathlib.Path(sys.argv[2])
body = sys.stdin.read().rstrip() + "\n"
begin, end = f"<!-- {name}:begin -->", f"<!-- {name}:end -->"
text = path.read_text() if path.exists() else "# Benchmarks\n\nEach section is written by a script in `scripts/bench/`; rerun it to refresh.\n"
block = f"{begin}\n{body}{end}"
if begin in text and end in text:
    head, rest = text.split(begin, 1)
    _, tail = rest.split(end, 1)
    text = head + block + tail
else:
    text = text.rstrip() + "\n\n" + block + "\n"
path.write_text(text)
