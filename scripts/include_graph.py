#!/usr/bin/env python3
"""Folder-level include graph of the workspace's C++ sources, and its cycles.

A node is `package/folder`: for a header include/<package>/<folder>/x.h and a source
src/<folder>/x.cpp of the same package the folder is the same node (`flagella_sim/outputs`);
headers directly under include/<package>/ and sources directly under src/ are
`package/(lib)`; files under a package's other folders (tools/, nodes/, lcm_io/, test/, ...) are
`package/<that folder>`. An edge A -> B means a file of A includes a header of B
("<package>/<folder>/..." or a path relative to the including file). Prints the edges (with the
number of includes) and every cycle among the nodes (strongly connected components of size > 1).

  python3 scripts/include_graph.py            # edges and cycles
  python3 scripts/include_graph.py --cycles   # cycles only; exit status 1 if there is one
"""
import os
import re
import sys
from collections import defaultdict

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "src")
INCLUDE = re.compile(r'^\s*#\s*include\s*[<"]([^>"]+)[>"]')
EXTENSIONS = (".h", ".hpp", ".cpp", ".def")


def node_of(package, rel):
    """rel: path of a file inside package/, e.g. include/flagella_sim/outputs/x.h."""
    parts = rel.split(os.sep)
    if parts[0] == "include" and len(parts) >= 3 and parts[1] == package:
        return package + "/" + (parts[2] if len(parts) > 3 else "(lib)")
    if parts[0] == "src":
        return package + "/" + (parts[1] if len(parts) > 2 else "(lib)")
    return package + "/" + (parts[0] if len(parts) > 1 else "(top)")


def main():
    packages = sorted(d for d in os.listdir(ROOT) if os.path.isdir(os.path.join(ROOT, d)))
    files = {}  # absolute path -> node
    for package in packages:
        base = os.path.join(ROOT, package)
        for dirpath, _, names in os.walk(base):
            for name in names:
                if name.endswith(EXTENSIONS):
                    path = os.path.join(dirpath, name)
                    files[os.path.normpath(path)] = node_of(package, os.path.relpath(path, base))
    edges = defaultdict(int)
    for path, node in files.items():
        with open(path, encoding="utf-8", errors="replace") as f:
            for line in f:
                m = INCLUDE.match(line)
                if not m:
                    continue
                target = None
                head = m.group(1).split("/")[0]
                if head in packages:
                    target = os.path.normpath(os.path.join(ROOT, head, "include", m.group(1)))
                local = os.path.normpath(os.path.join(os.path.dirname(path), m.group(1)))
                if local in files:
                    target = local
                if target in files and files[target] != node:
                    edges[(node, files[target])] += 1
    graph = defaultdict(set)
    for a, b in edges:
        graph[a].add(b)
    cycles = strongly_connected(sorted(set(files.values())), graph)
    if "--cycles" not in sys.argv:
        for (a, b), n in sorted(edges.items()):
            print(f"{a} -> {b} ({n})")
        print()
    if cycles:
        for component in cycles:
            print("cycle: " + " <-> ".join(sorted(component)))
            for a in sorted(component):
                for b in sorted(graph[a] & set(component)):
                    print(f"  {a} -> {b}")
    else:
        print("no cycles")
    return 1 if cycles else 0


def strongly_connected(nodes, graph):
    """Tarjan's algorithm; returns the components with more than one node."""
    index, low, stack, on_stack, result = {}, {}, [], set(), []
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
                result.append(component)

    for v in nodes:
        if v not in index:
            visit(v)
    return result


if __name__ == "__main__":
    sys.exit(main())
