#!/usr/bin/env python3
"""The module graph of bemsurg, derived from the #include lines, checked against the layer order.

Every file under include/bemsurg/ and src/ belongs to a module: include/bemsurg/<module>/... and
src/<module>/... by folder; the top-level headers (config, error, types, number_text, ...) to
`core`; `elastostatic_solver*` (the one-call facade, kept at the top of include/ for its users)
to `elastostatics`. An edge A -> B exists when a file of A includes a header of B. docs/design.md
("Module order") gives the order; an edge must point to a module earlier in it, so the graph has no
cycle by construction. The script reports every edge that does not (with the file and line that
makes it), every cycle, and can draw the graph as SVG without any third-party package.

  python3 scripts/module-graph.py                 # check; exit 1 on a violation
  python3 scripts/module-graph.py --svg docs/images/module-graph.svg --dot build/modules.dot
"""
import argparse
import math
import re
import sys
from collections import defaultdict
from pathlib import Path

# Lowest first. A module may include only modules before it (docs/design.md, "Module order").
ORDER = ["core", "mesh", "kernels", "quadrature", "solvers", "assembly", "elastostatics", "post",
         "presolution", "cutting", "verification", "io", "haptics", "cli"]
# Edges the order allows but only through the headers listed: the haptics adapter links
# bemsurg::numerics alone (CMakeLists.txt), so of io it may use only the action model, whose
# definitions are compiled there (src/io/action_model.cpp), never the JSON readers.
RESTRICTED = {("haptics", "io"): {"io/action_script.hpp"}}
# Headers that gather others on purpose and so belong to no layer.
AGGREGATORS = {"bemsurg.hpp"}
INCLUDE = re.compile(r'^\s*#\s*include\s*"bemsurg/([^"]+)"')


def module_of_header(rel):
    """Module of a header named as in #include "bemsurg/<rel>"."""
    parts = rel.split("/")
    if parts[-1].startswith("elastostatic_solver"):
        return "elastostatics"
    if len(parts) == 1:
        stem = parts[0][:-4] if parts[0].endswith(".hpp") else parts[0]
        return stem if stem in ORDER else "core"  # bemsurg/mesh.hpp is the mesh module's header
    if parts[0] == "impl":
        return "core"
    return parts[0]


def module_of_file(root, path):
    rel = path.relative_to(root).as_posix()
    if rel.startswith("include/bemsurg/"):
        return module_of_header(rel[len("include/bemsurg/"):])
    parts = rel.split("/")  # src/<module>/...
    if path.name.startswith("elastostatic_solver"):
        return "elastostatics"
    return parts[1] if len(parts) > 2 else "core"


def collect(root):
    """edges[(a, b)] = [(file, line), ...] for every include of module b from module a."""
    edges = defaultdict(list)
    files = sorted(p for d in ("include/bemsurg", "src") for p in (root / d).rglob("*")
                   if p.suffix in (".hpp", ".cpp", ".h") and p.is_file())
    unknown = []
    for path in files:
        if path.name in AGGREGATORS and path.parent == root / "include/bemsurg":
            continue
        a = module_of_file(root, path)
        if a not in ORDER:
            unknown.append(f"{path.relative_to(root)}: module '{a}' is not in ORDER")
            continue
        for number, line in enumerate(path.read_text(encoding="utf-8").splitlines(), 1):
            m = INCLUDE.match(line)
            if not m:
                continue
            b = module_of_header(m.group(1))
            if b not in ORDER:
                unknown.append(f"{path.relative_to(root)}:{number}: includes '{m.group(1)}' of no known module")
            elif a != b:
                edges[(a, b)].append((path.relative_to(root).as_posix(), number))
                allowed = RESTRICTED.get((a, b))
                if allowed is not None and m.group(1) not in allowed:
                    unknown.append(f"{path.relative_to(root)}:{number}: {a} may include only {sorted(allowed)} of {b}, "
                                   f"not '{m.group(1)}'")
    return edges, unknown


def find_cycles(edges):
    """Strongly connected components of more than one module (Tarjan)."""
    graph = defaultdict(set)
    for a, b in edges:
        graph[a].add(b)
    index, low, stack, on_stack, out = {}, {}, [], set(), []

    def visit(v):
        index[v] = low[v] = len(index)
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
                out.append(sorted(component, key=ORDER.index))

    for v in ORDER:
        if v not in index:
            visit(v)
    return out


def write_dot(edges, path):
    lines = ["digraph bemsurg_modules {", "  rankdir=BT;", "  node [shape=box];"]
    for (a, b), sites in sorted(edges.items()):
        lines.append(f'  "{a}" -> "{b}" [label="{len(sites)}"];')
    lines.append("}")
    Path(path).write_text("\n".join(lines) + "\n", encoding="utf-8")


def write_svg(edges, path):
    """Layers bottom-up by the longest path to `core`; arrows from includer to included."""
    used = [m for m in ORDER if any(m in e for e in edges) or m == "core"]
    level = {}
    for m in used:  # ORDER is topological, so every target is placed before its sources
        targets = [b for (a, b) in edges if a == m and b in level]  # a wrong-way edge is drawn, not layered
        level[m] = 1 + max((level[b] for b in targets), default=-1)
    rows = defaultdict(list)
    for m in used:
        rows[level[m]].append(m)
    width, box_w, box_h, gap_y = 760, 116, 30, 64
    height = (max(rows) + 1) * gap_y + 40
    pos = {}
    for lv, members in rows.items():
        y = height - 30 - lv * gap_y
        for i, m in enumerate(members):
            x = width * (i + 1) / (len(members) + 1)
            pos[m] = (x, y)
    out = [f'<svg xmlns="http://www.w3.org/2000/svg" width="{width}" height="{height}" '
           f'viewBox="0 0 {width} {height}" font-family="sans-serif" font-size="13">',
           '<defs><marker id="a" viewBox="0 0 10 10" refX="10" refY="5" markerWidth="7" '
           'markerHeight="7" orient="auto"><path d="M0,0 L10,5 L0,10 z" fill="#555"/></marker></defs>',
           f'<rect width="{width}" height="{height}" fill="white"/>']
    for (a, b), sites in sorted(edges.items()):
        (x1, y1), (x2, y2) = pos[a], pos[b]
        # Leave the source at its bottom edge, enter the target at its top edge (or side when level).
        dx, dy = x2 - x1, y2 - y1
        length = math.hypot(dx, dy) or 1.0
        shrink_a = min(box_h / 2 / max(abs(dy) / length, 1e-9), box_w / 2 / max(abs(dx) / length, 1e-9))
        shrink_b = shrink_a
        sx, sy = x1 + dx / length * shrink_a, y1 + dy / length * shrink_a
        ex, ey = x2 - dx / length * (shrink_b + 2), y2 - dy / length * (shrink_b + 2)
        out.append(f'<line x1="{sx:.1f}" y1="{sy:.1f}" x2="{ex:.1f}" y2="{ey:.1f}" stroke="#888" '
                   f'stroke-width="{1 + min(len(sites), 20) / 8:.2f}" marker-end="url(#a)"/>')
    for m, (x, y) in pos.items():
        out.append(f'<rect x="{x - box_w / 2:.1f}" y="{y - box_h / 2:.1f}" width="{box_w}" height="{box_h}" '
                   f'rx="5" fill="#eef3fb" stroke="#35608f"/>')
        out.append(f'<text x="{x:.1f}" y="{y + 4:.1f}" text-anchor="middle">{m}</text>')
    out.append("</svg>")
    Path(path).parent.mkdir(parents=True, exist_ok=True)
    Path(path).write_text("\n".join(out) + "\n", encoding="utf-8")


# Modules whose header the umbrella leaves out, and why (docs/design.md, "Module order").
NOT_IN_UMBRELLA = {"haptics": "a library of its own (bemsurg::haptics), linked only by device programs",
                   "cli": "the command-line program, not a library"}


def check_module_headers(root):
    """Every public header is reachable from its module header (bemsurg/<module>.hpp), and every
    module header but those in NOT_IN_UMBRELLA from bemsurg/bemsurg.hpp. Deprecated forwarding
    headers (they carry `#pragma GCC warning`) belong to no module header."""
    base = root / "include/bemsurg"
    problems = []
    umbrella = (base / "bemsurg.hpp").read_text(encoding="utf-8")
    umbrella_includes = set(re.findall(r'#include "bemsurg/([^"]+)"', umbrella))
    for path in sorted(base.rglob("*.hpp")):
        rel = path.relative_to(base).as_posix()
        text = path.read_text(encoding="utf-8")
        if "/impl/" in "/" + rel or rel.startswith("impl/") or "#pragma GCC warning" in text or rel in AGGREGATORS:
            continue
        module = module_of_header(rel)
        if "/" not in rel:  # a top-level header: a module header, the facade or a core header
            if rel[:-4] in NOT_IN_UMBRELLA or rel == "config.hpp":
                continue
            if rel not in umbrella_includes:
                problems.append(f"bemsurg/bemsurg.hpp does not include bemsurg/{rel}")
            continue
        module_header = base / f"{module}.hpp"
        if not module_header.exists():
            problems.append(f"module '{module}' has no module header bemsurg/{module}.hpp (for {rel})")
            continue
        if f'#include "bemsurg/{rel}"' not in module_header.read_text(encoding="utf-8"):
            problems.append(f"bemsurg/{module}.hpp does not include bemsurg/{rel}")
    return problems


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--root", default=Path(__file__).resolve().parent.parent, type=Path)
    parser.add_argument("--svg", help="write the graph as SVG here")
    parser.add_argument("--dot", help="write the graph as Graphviz DOT here")
    parser.add_argument("--list", action="store_true", help="print every edge with its include count")
    args = parser.parse_args()

    edges, unknown = collect(args.root)
    problems = list(unknown) + check_module_headers(args.root)
    for (a, b), sites in sorted(edges.items()):
        if ORDER.index(b) > ORDER.index(a):
            where = ", ".join(f"{f}:{n}" for f, n in sites[:4]) + (" ..." if len(sites) > 4 else "")
            problems.append(f"edge against the module order: {a} -> {b} ({where})")
    for cycle in find_cycles(edges):
        problems.append("module cycle: " + " <-> ".join(cycle))
    if args.list:
        for (a, b), sites in sorted(edges.items(), key=lambda e: (ORDER.index(e[0][0]), ORDER.index(e[0][1]))):
            print(f"{a} -> {b}: {len(sites)}")
    if args.svg:
        write_svg(edges, args.svg)
    if args.dot:
        write_dot(edges, args.dot)
    if problems:
        print("module-graph: FAILED", file=sys.stderr)
        for p in problems:
            print("  " + p, file=sys.stderr)
        return 1
    print(f"module-graph: {len(edges)} edges between {len({m for e in edges for m in e})} modules, "
          f"no cycle, all in the order {' < '.join(ORDER)}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
