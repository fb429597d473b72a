#!/usr/bin/env python3
"""check_layers.py - the build's layer check (docs/architecture.md, "Layers").

Two checks over the library, both against the one table LAYERS below:

1. includes: every source and header under src/ and include/rockfuzz/ may
   include, directly or through other project headers, only headers of its
   own module or of a module it may depend on;
2. symbols: every object file of the library (the arguments, or none) may
   use only symbols defined in its own module or in a module it may depend
   on, and no group of object files calls each other in a circle (a file
   circle hides a missing lower file; see architecture.md).

Usage: check_layers.py SOURCE_DIR [OBJECT.o ...]    (exit 1 on a violation)
       check_layers.py --selftest                    (the checker on made-up trees)
"""
import os
import re
import subprocess
import sys

# module -> the modules it may depend on (its own is always allowed).  Lower
# layers first; the physics modules (fuzzy, material, impact, fem,
# trajectory) never reach tm or study.
LAYERS = {
    "core": set(),
    "plot": {"core"},
    "fuzzy": {"core"},
    "material": {"core"},
    "impact": {"core", "material"},
    "fem": {"core", "material", "impact"},
    "model": {"core", "material", "impact", "fem"},
    "trajectory": {"core", "plot", "material", "impact", "fem", "model"},
    "tm": {"core", "fuzzy", "model"},
    "study": {"core", "plot", "fuzzy", "material", "impact", "fem", "model", "trajectory", "tm"},
    "cli": {"core", "plot", "fuzzy", "material", "impact", "fem", "model", "trajectory", "tm", "study"},
}

# Public headers (include/rockfuzz/NAME.h) -> module.
PUBLIC = {
    "status": "core", "fuzzy": "fuzzy", "material": "material", "impact": "impact", "mdr": "impact",
    "fem": "fem", "fem3d": "fem", "model": "model", "impact_model": "model", "trajectory": "trajectory", "terrain": "trajectory", "block": "trajectory",
    "presets": "trajectory",
    "tm": "tm", "analysis": "tm", "study": "study", "study_run": "study", "runner": "study",
    "store": "study", "mpi": "study", "report": "study",
}

INCLUDE_RE = re.compile(r'^\s*#\s*include\s+"([^"]+)"', re.M)


def module_of(path, root):
    """The module of a project file (relative or absolute path), or None."""
    rel = os.path.relpath(path, root).replace(os.sep, "/")
    parts = rel.split("/")
    if parts[0] == "include" and len(parts) == 3 and parts[1] == "rockfuzz":
        return PUBLIC.get(os.path.splitext(parts[2])[0], "unknown public header")
    if parts[0] == "src" and len(parts) >= 3:
        return parts[1]
    return None


def resolve(name, including, root):
    """The project file that `#include "name"` in `including` reads, or None (a system header)."""
    for base in (os.path.dirname(including), os.path.join(root, "src"), os.path.join(root, "include")):
        p = os.path.normpath(os.path.join(base, name))
        if os.path.isfile(p):
            return p
    return None


def include_graph(root):
    """{file: set(files it includes directly)} over src/ and include/rockfuzz/."""
    files = []
    for top in ("src", "include"):
        for d, _, names in os.walk(os.path.join(root, top)):
            files += [os.path.join(d, n) for n in names if n.endswith((".c", ".h"))]
    graph = {}
    for f in files:
        with open(f, encoding="utf-8", errors="replace") as fh:
            text = fh.read()
        graph[f] = {p for p in (resolve(n, f, root) for n in INCLUDE_RE.findall(text)) if p}
    return graph


def check_includes(graph, module, root):
    """Violations: (file, header reached, chain) where the header's module is not allowed."""
    bad = []
    for f in sorted(graph):
        m = module(f)
        if m not in LAYERS:
            continue
        seen, stack = {f: None}, [f]
        while stack:
            cur = stack.pop()
            for h in graph.get(cur, ()):
                if h in seen:
                    continue
                seen[h] = cur
                stack.append(h)
                hm = module(h)
                if hm != m and hm not in LAYERS[m]:
                    chain, c = [h], cur
                    while c:
                        chain.append(c)
                        c = seen[c]
                    bad.append((f, h, [os.path.relpath(x, root) for x in reversed(chain)]))
    return bad


def symbol_graph(objects, name_of):
    """{object name: set(object names whose symbols it uses)} from one nm run."""
    defined, used = {}, {name_of(o): set() for o in objects}
    out = subprocess.run(["nm", "-A"] + list(objects), capture_output=True, text=True, check=True).stdout
    for line in out.splitlines():
        obj, _, rest = line.rpartition(".o:")
        name, p = name_of(obj + ".o"), rest.split()
        if len(p) == 3 and p[1] in "TDBRCV":
            defined[p[2]] = name
        elif len(p) == 2 and p[0] == "U":
            used[name].add(p[1])
    return {n: {defined[s] for s in syms if s in defined and defined[s] != n} for n, syms in used.items()}


def check_symbols(graph, module):
    """Violations: (user, provider) pairs whose modules are not allowed."""
    return sorted((a, b) for a, targets in graph.items() for b in targets
                  if module(a) in LAYERS and module(b) != module(a) and module(b) not in LAYERS[module(a)])


def circles(graph):
    """The strongly connected groups of more than one node (Tarjan, iterative)."""
    index, low, on, stack, out, counter = {}, {}, set(), [], [], [0]
    for start in sorted(graph):
        if start in index:
            continue
        work = [(start, iter(sorted(graph.get(start, ()))))]
        index[start] = low[start] = counter[0]
        counter[0] += 1
        stack.append(start)
        on.add(start)
        while work:
            v, it = work[-1]
            w = next(it, None)
            if w is not None:
                if w not in index:
                    index[w] = low[w] = counter[0]
                    counter[0] += 1
                    stack.append(w)
                    on.add(w)
                    work.append((w, iter(sorted(graph.get(w, ())))))
                elif w in on:
                    low[v] = min(low[v], index[w])
                continue
            work.pop()
            if work:
                low[work[-1][0]] = min(low[work[-1][0]], low[v])
            if low[v] == index[v]:
                group = []
                while True:
                    w = stack.pop()
                    on.discard(w)
                    group.append(w)
                    if w == v:
                        break
                if len(group) > 1:
                    out.append(sorted(group))
    return out


def object_name(path):
    """CMakeFiles/rockfuzz.dir/src/fem/x.c.o -> src/fem/x.c"""
    p = path.replace(os.sep, "/")
    i = p.rfind("/src/")
    return p[i + 1:-2] if i >= 0 and p.endswith(".o") else p


def run(root, objects):
    root = os.path.abspath(root)
    module = lambda f: module_of(f, root)
    problems = 0
    for f, h, chain in check_includes(include_graph(root), module, root):
        problems += 1
        print(f"layers: {os.path.relpath(f, root)} ({module(f)}) reaches {os.path.relpath(h, root)} "
              f"({module(h)}): {' -> '.join(chain)}")
    if objects:
        graph = symbol_graph(objects, object_name)
        smod = lambda n: module_of(os.path.join(root, n), root)
        for a, b in check_symbols(graph, smod):
            problems += 1
            print(f"layers: {a} ({smod(a)}) uses symbols of {b} ({smod(b)})")
        for group in circles(graph):
            problems += 1
            print("layers: file circle: " + " <-> ".join(group))
    n_obj = len(objects)
    print(f"check_layers: {problems} violation(s) ({len(LAYERS)} modules, {n_obj} object files)")
    return 1 if problems else 0


def selftest():
    """The checks on made-up graphs: each must find what was put in."""
    mod = lambda f: f.split("/")[1]
    g = {"src/fem/a.c": {"src/study/s.h"}, "src/study/s.h": set(), "src/study/b.c": {"src/fem/f.h"},
         "src/fem/f.h": set()}
    bad = check_includes(g, mod, "/")
    assert [(b[0], b[1]) for b in bad] == [("src/fem/a.c", "src/study/s.h")], bad
    g = {"src/trajectory/t.h": {"src/core/c.h"}, "src/core/c.h": {"src/tm/x.h"}, "src/tm/x.h": set(),
         "src/trajectory/u.c": {"src/trajectory/t.h"}}
    bad = {b[0] for b in check_includes(g, mod, "/")}
    assert bad == {"src/trajectory/u.c", "src/trajectory/t.h", "src/core/c.h"}, bad  # indirect too
    s = {"src/fem/a.c": {"src/study/b.c"}, "src/study/b.c": {"src/fem/a.c"}}
    assert check_symbols(s, mod) == [("src/fem/a.c", "src/study/b.c")]
    c = {"a": {"b"}, "b": {"c"}, "c": {"a"}, "d": {"a"}, "e": {"e"}}
    assert circles(c) == [["a", "b", "c"]], circles(c)
    assert circles({"a": {"b"}, "b": set()}) == []
    assert object_name("/x/CMakeFiles/rockfuzz.dir/src/fem/a.c.o") == "src/fem/a.c"
    print("check_layers selftest: 6 passed, 0 failed")
    return 0


if __name__ == "__main__":
    if sys.argv[1:] == ["--selftest"]:
        sys.exit(selftest())
    if len(sys.argv) < 2:
        print(__doc__)
        sys.exit(2)
    sys.exit(run(sys.argv[1], sys.argv[2:]))
