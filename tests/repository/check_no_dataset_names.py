#!/usr/bin/env python3
"""Fails when a comment in a shipped config or in the SDK's or a plugin's sources (tests aside)
names one of the data folder's datasets: a setting says its physical reason, not the log it was
tuned on (issue 41). Datasets are the data folder's own: every folder name, and for the laser
logs their place (the folder name's first word, and a Freiburg log's site)."""
import os
import pathlib
import re
import sys

root = pathlib.Path(sys.argv[1])
data = pathlib.Path(os.environ.get("PLUGSLAM_DATA") or root.resolve().parent / "shared" / "data")
if not data.is_dir():
    print(f"SKIPPED: no data folder at {data} (set PLUGSLAM_DATA): nothing to check against")
    sys.exit(0)

names = set()
for area in data.iterdir():
    if not area.is_dir():
        continue
    for d in area.iterdir():
        if not d.is_dir():
            continue
        if d.name.count("-") >= 2:  # a folder name, not a method's (se-sync)
            names.add(d.name.lower())
        if area.name == "laser2d":
            words = d.name.lower().split("-")
            names.add(words[0])
            if words[0] == "freiburg" and words[1].isalpha():
                names.add(words[1])
pattern = re.compile(r"(?<![\w-])(" + "|".join(sorted(map(re.escape, names), key=len, reverse=True)) + r")(?![\w])",
                     re.IGNORECASE)

def comments(path):
    """(line number, comment text) of the file's comments."""
    text = path.read_text(errors="replace").splitlines()
    yaml = path.suffix in (".yaml", ".yml")
    for n, line in enumerate(text, 1):
        if yaml:
            # A '#' outside quotes starts a comment.
            m = re.search(r"(^|\s)#(.*)$", line)
            if m:
                yield n, m.group(2)
        else:
            i = line.find("//")
            if i >= 0:
                yield n, line[i + 2:]
            elif line.lstrip().startswith(("*", "/*")):
                yield n, line

files = list((root / "configs").rglob("*.yaml"))
for top in ("sdk", "plugins"):
    for p in (root / top).rglob("*"):
        if p.suffix in (".h", ".cpp", ".in") and "tests" not in p.relative_to(root).parts:
            files.append(p)
found = []
for p in sorted(files):
    for n, c in comments(p):
        m = pattern.search(c)
        if m:
            found.append(f"{p.relative_to(root)}:{n}: names the dataset '{m.group(1)}': {c.strip()}")
if found:
    print("\n".join(found))
    print(f"{len(found)} comment(s) name a dataset: say the physical reason instead")
    sys.exit(1)
print(f"checked {len(files)} files against {len(names)} dataset names: none named")
