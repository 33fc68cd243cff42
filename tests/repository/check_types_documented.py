#!/usr/bin/env python3
"""Fails when a plugin's registered type is missing from its README, or a shipped config names a
type the configuration reference does not list.

The registered types are read from docs/config-reference.md, which `plugslam reference` writes
from the registry and the test config_reference_is_current keeps equal to it: so this check needs
no build, and a type added without regenerating the reference fails there first. A README names
a type by its full YAML name (`laser2d.PointMapSlice`), since that is what a reader copies into a
config. The SDK's built-in types (`sdk.`) have no plugin README: their headers document them.
Configs are configs/*.yaml and configs/parts/*.yaml; a value of any `type:` key (or a --set style
key ending in `.type`) outside comments counts.

Usage: check_types_documented.py SOURCE_DIR
"""
import glob
import os
import re
import sys

HEADING = re.compile(r"^### `([A-Za-z_]\w*)\.([A-Za-z_]\w*)` \(")
TYPE_VALUE = re.compile(r"(?:^|[\s{,.-])type:\s*[\"']?([^\s,}\]\"'#]+)")


def registered(root):
    """{plugin: [Type, ...]} from the generated reference."""
    types = {}
    with open(os.path.join(root, "docs", "config-reference.md"), encoding="utf-8") as f:
        for line in f:
            m = HEADING.match(line)
            if m:
                types.setdefault(m.group(1), []).append(m.group(2))
    return types


def config_types(path):
    """(line number, type name) of every `type:` value in a config, comments dropped."""
    with open(path, encoding="utf-8") as f:
        for number, raw in enumerate(f, 1):
            text = re.sub(r"(^|\s)#.*$", "", raw)
            for m in TYPE_VALUE.finditer(text):
                yield number, m.group(1)


def main():
    root = sys.argv[1]
    types = registered(root)
    if not types:
        print("docs/config-reference.md lists no type: is it the generated reference?")
        return 1
    problems = []
    for plugin, names in sorted(types.items()):
        if plugin == "sdk":
            continue
        readme = os.path.join(root, "plugins", plugin, "README.md")
        if not os.path.exists(readme):
            problems.append(f"plugins/{plugin}/README.md: missing (the plugin registers "
                            f"{len(names)} types)")
            continue
        with open(readme, encoding="utf-8") as f:
            text = f.read()
        for name in names:
            if not re.search(r"(?<![\w.])" + re.escape(f"{plugin}.{name}") + r"(?!\w)", text):
                problems.append(f"plugins/{plugin}/README.md: does not name `{plugin}.{name}`, "
                                "a type the plugin registers")
    known = {f"{p}.{n}" for p, names in types.items() for n in names}
    configs = sorted(glob.glob(os.path.join(root, "configs", "*.yaml")) +
                     glob.glob(os.path.join(root, "configs", "parts", "*.yaml")))
    for path in configs:
        for number, name in config_types(path):
            if name not in known:
                problems.append(f"{os.path.relpath(path, root)}:{number}: type '{name}' is not in "
                                "docs/config-reference.md")
    for p in problems:
        print(p)
    print(f"{sum(len(n) for n in types.values())} registered types, {len(configs)} configs: "
          f"{len(problems)} problem(s)")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
