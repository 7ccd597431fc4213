#!/usr/bin/env python3
"""The repository stands on its own: no file cites the internal design document.

Code comments, help texts, the scenario schema and the docs cite the repository's own
documents (docs/theory.md, docs/validation.md, docs/dr2.md, docs/developer-guide.md,
docs/user-guide.md). This check fails, listing every file:line, when a file under src,
tests, docs, scripts, examples, bench, fuzz or cmake, README.md or a CMakeLists.txt
mentions DESIGN.md (or "DESIGN §N", "DESIGN section N"). This script is the one exception.

Usage: check_self_contained_citations.py [REPOSITORY_ROOT]   (default: this script's ../)
"""
import os
import re
import sys

ROOTS = ["src", "tests", "docs", "scripts", "examples", "bench", "fuzz", "cmake"]
FILES = ["README.md", "CMakeLists.txt"]
PATTERN = re.compile(r"DESIGN\.md|DESIGN(?:'s)? ?§|DESIGN section")


def candidates(root):
    for name in FILES:
        path = os.path.join(root, name)
        if os.path.isfile(path):
            yield path
    for top in ROOTS:
        for folder, dirs, files in os.walk(os.path.join(root, top)):
            dirs[:] = [d for d in dirs if not d.startswith(".") and d != "build"]
            for name in files:
                yield os.path.join(folder, name)


def main():
    root = os.path.abspath(sys.argv[1] if len(sys.argv) > 1 else os.path.join(os.path.dirname(__file__), ".."))
    me = os.path.realpath(__file__)
    hits = []
    for path in sorted(candidates(root)):
        if os.path.realpath(path) == me:
            continue
        try:
            with open(path, "rb") as f:
                data = f.read()
        except OSError:
            continue
        if b"\0" in data[:4096]:  # binary
            continue
        for n, line in enumerate(data.decode("utf-8", errors="replace").splitlines(), 1):
            if PATTERN.search(line):
                hits.append(f"{os.path.relpath(path, root)}:{n}: {line.strip()}")
    if hits:
        print("Files cite the internal design document; cite docs/theory.md, docs/validation.md, docs/dr2.md, "
              "docs/developer-guide.md or docs/user-guide.md instead:")
        print("\n".join(hits))
        return 1
    print("no file cites the internal design document")
    return 0


if __name__ == "__main__":
    sys.exit(main())
