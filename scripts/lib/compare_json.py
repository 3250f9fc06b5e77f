#!/usr/bin/env python3
"""compare_json.py OLD NEW: the two JSON documents field by field, skipping the
fields that measure time or describe the run rather than its results (keys
matching SKIP: timings, dates, commands, devices, paths of executables).
Prints each differing path and exits 1; exit 0 when equal. Floats are equal
only when identical: a refactoring must not change a single result."""
import json
import re
import sys

SKIP = re.compile(r"(_ms$|\sms$|^ms$|_seconds$|^seconds$|time|date|^passes|clock|^command$|executable|^device$|^gl$|uptime"
                  r"|^host|_per_second$|^summaries$)")


def walk(a, b, path, out):
    if isinstance(a, dict) and isinstance(b, dict):
        for k in sorted(set(a) | set(b)):
            if SKIP.search(k):
                continue
            if k not in a or k not in b:
                out.append(f"{path}/{k}: only in {'new' if k in b else 'old'}")
            else:
                walk(a[k], b[k], f"{path}/{k}", out)
    elif isinstance(a, list) and isinstance(b, list):
        if len(a) != len(b):
            out.append(f"{path}: {len(a)} vs {len(b)} items")
        for i, (x, y) in enumerate(zip(a, b)):
            walk(x, y, f"{path}[{i}]", out)
    elif a != b:
        out.append(f"{path}: {a!r} vs {b!r}")


def main():
    old, new = (json.load(open(p)) for p in sys.argv[1:3])
    out = []
    walk(old, new, "", out)
    for line in out[:20]:
        print(f"{sys.argv[2]}: {line}")
    if len(out) > 20:
        print(f"{sys.argv[2]}: ... {len(out) - 20} more differences")
    return 1 if out else 0


if __name__ == "__main__":
    sys.exit(main())
