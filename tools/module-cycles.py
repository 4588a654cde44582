#!/usr/bin/env python3
"""Lists the modules of the library that depend on each other in a cycle.

    tools/module-cycles.py [root]   (default: the repository this script is in)

A module is a header and its source of the same name (include/levelfuse/<floor>/X.h,
src/<floor>/X.cc, or a private src/<floor>/X.h); it depends on every module
whose header its header or its source includes. Exits 1 if any modules form a
cycle (A includes B's header while B includes A's, directly or through others),
and prints each cycle's modules.
"""
import pathlib
import re
import sys

INCLUDE = re.compile(r'^\s*#\s*include\s*[<"]([^">]+)[">]', re.M)


def modules(root):
    """module name -> set of module names it includes, for src/ and include/levelfuse/."""
    files = {}
    for path in list((root / "include/levelfuse").rglob("*.h")) + list((root / "src").rglob("*.cc")) + \
            list((root / "src").rglob("*.h")):
        rel = path.relative_to(root)
        parts = rel.parts
        floor_parts = parts[2:-1] if parts[0] == "include" else parts[1:-1]
        if parts[0] == "src" and parts[1] == "python":
            continue  # the Python module is one unit of its own, above the library
        name = "/".join(floor_parts + (path.stem,))
        files.setdefault(name, []).append(path)
    known = set(files)
    graph = {}
    for name, paths in files.items():
        floor = name.rsplit("/", 1)[0] if "/" in name else ""
        deps = set()
        for path in paths:
            for target in INCLUDE.findall(path.read_text(errors="replace")):
                target = re.sub(r"\.(h|cc)$", "", target)
                if target.startswith("levelfuse/"):
                    dep = target[len("levelfuse/"):]
                elif "/" not in target and floor:
                    dep = floor + "/" + target
                else:
                    dep = target
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
