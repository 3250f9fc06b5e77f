#!/usr/bin/env python3
"""check_layers.py LAYERS.txt SOURCE_DIR: fails on an include that goes up a layer.

LAYERS.txt (written by CMakeLists.txt's ml_layer() calls) has one line per
layer: `<target> <folder> <dep target>...`, and may add `+<folder>` tokens (a
folder outside the layers that a layer may include, e.g. bench's use of
tests/support) and `twin <header>...` lines (headers of the twins, which only
tests and benches may include). A layer may include headers of its own folder
and of every folder its DEPS reach, transitively, as CMake's PUBLIC links do.
Every `#include "a/b/c.hpp"` in a layer's folder (not its subfolders) that
names a folder of host/, gl/, bench/ or tests/ outside that set is reported as
`file:line: ...` and the exit status is 1. Standard library only: it runs
before anything compiles.
"""
import os
import re
import sys

INCLUDE = re.compile(r'^\s*#\s*include\s+"([^"]+)"')
ROOTS = ("host/", "gl/", "bench/", "tests/")


def read_layers(path):
    folders, deps, extra, twins = {}, {}, {}, set()
    with open(path) as f:
        for line in f:
            words = line.split()
            if not words:
                continue
            if words[0] == "twin":
                twins.update(words[1:])
                continue
            name, folder, rest = words[0], words[1], words[2:]
            folders[name] = folder
            deps[name] = [w for w in rest if not w.startswith("+")]
            extra[name] = {w[1:] for w in rest if w.startswith("+")}
    return folders, deps, extra, twins


def reach(name, folders, deps, extra, seen=None):
    seen = set() if seen is None else seen
    if name in seen:
        return set()
    seen.add(name)
    allowed = {folders[name]} | extra.get(name, set())
    for d in deps.get(name, []):
        if d not in folders:
            sys.exit(f"check_layers: layer {name} names an unknown layer {d}")
        allowed |= reach(d, folders, deps, extra, seen)
    return allowed


def check(root, folders, deps, extra, twins):
    problems = []
    for name, folder in sorted(folders.items()):
        allowed = reach(name, folders, deps, extra)
        directory = os.path.join(root, folder)
        if not os.path.isdir(directory):
            continue
        for entry in sorted(os.listdir(directory)):
            if not entry.endswith((".cpp", ".hpp", ".h")):
                continue
            rel = f"{folder}/{entry}"
            is_twin = rel.rsplit(".", 1)[0] + ".hpp" in twins
            with open(os.path.join(directory, entry), encoding="utf-8", errors="replace") as f:
                for number, line in enumerate(f, 1):
                    m = INCLUDE.match(line)
                    if not m or not m.group(1).startswith(ROOTS):
                        continue
                    target = m.group(1)
                    if os.path.dirname(target) not in allowed:
                        problems.append(f"{rel}:{number}: includes {target}, but {folder} ({name}) does not build on "
                                        f"{os.path.dirname(target)}: declare the dependency in CMakeLists.txt "
                                        f"(ml_layer) if it is one, or move the code down a layer")
                    elif target in twins and not is_twin and name != "bench":
                        problems.append(f"{rel}:{number}: includes the twin {target}: twins are for tests and benches")
    return problems


def main():
    if len(sys.argv) != 3:
        sys.exit("usage: check_layers.py LAYERS.txt SOURCE_DIR")
    folders, deps, extra, twins = read_layers(sys.argv[1])
    problems = check(sys.argv[2], folders, deps, extra, twins)
    for p in problems:
        print(p, file=sys.stderr)
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
