#!/usr/bin/env python3
"""Lists the modules of the library that depend on each other in a cycle.

    tools/module-cycles.py [root]   (default: the repository this script is in)

A module is a header and its source of the same name (include/levelfuse/<folder>/X.h,
src/<folder>/X.cc, or a private src/<folder>/X.h); it depends on every module
whose header its header or its source includes (a private header by its path
from the including file). Exits 1 if any modules form a
cycle (A includes B's header while B includes A's, directly or through others),
and prints each cycle's modules.
"""
import os
import pathlib
import re
import sys

INCLUDE = re.compile(r'^\s*#\s*include\s*([<"])([^">]+)[">]', re.M)


def module_name(root, path):
    """The module a file of src/ or include/levelfuse/ belongs to ("io/scans/E57Scans"), or None."""
    parts = path.relative_to(root).parts
    if parts[0] == "include" and parts[1:2] == ("levelfuse",):
        folder_parts = parts[2:-1]
    elif parts[0] == "src":
        folder_parts = parts[1:-1]
    else:
        return None
    return "/".join(folder_parts + (path.stem,))


def modules(root):
    """module name -> set of module names it includes, for src/ and include/levelfuse/."""
    files = {}
    for path in list((root / "include/levelfuse").rglob("*.h")) + list((root / "src").rglob("*.cc")) + \
            list((root / "src").rglob("*.h")):
        parts = path.relative_to(root).parts
        if parts[0] == "src" and parts[1] == "python":
            continue  # the Python module is one unit of its own, above the library
        files.setdefault(module_name(root, path), []).append(path)
    known = set(files)
    graph = {}
    for name, paths in files.items():
        deps = set()
        for path in paths:
            for bracket, target in INCLUDE.findall(path.read_text(errors="replace")):
                if target.startswith("levelfuse/"):
                    dep = re.sub(r"\.(h|cc)$", "", target[len("levelfuse/"):])
                elif bracket == '"':  # a private header, beside the file or in a folder near it
                    resolved = pathlib.Path(os.path.normpath(path.parent / target))
                    dep = module_name(root, resolved) if resolved.is_relative_to(root) else None
                else:
                    dep = None
                if dep in known and dep != name:
                    deps.add(dep)
        graph[name] = deps
    return graph


def cycles(graph):
    """The strongly connected components of more than one module (Tarjan)."""
    index, low, on_stack, stack, found = {}, {}, set(), [], []
    counter = [0]

    def visit(v):
        index[v] = low[v] = counter[0]
        counter[0] += 1
        stack.append(v)
        on_stack.add(v)
        for w in sorted(graph[v]):
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on_stack:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            component = []
            while True:
                w = stack.pop()
                on_stack.discard(w)
                component.append(w)
                if w == v:
                    break
            if len(component) > 1:
                found.append(sorted(component))

    sys.setrecursionlimit(10000)
    for v in sorted(graph):
        if v not in index:
            visit(v)
    return found


def main():
    root = pathlib.Path(sys.argv[1] if len(sys.argv) > 1 else pathlib.Path(__file__).resolve().parent.parent)
    graph = modules(root)
    found = cycles(graph)
    for component in found:
        print("modules that include each other: " + ", ".join(component))
        for a in component:
            print(f"  {a} includes " + ", ".join(sorted(d for d in graph[a] if d in component)))
    return 1 if found else 0


if __name__ == "__main__":
    sys.exit(main())
