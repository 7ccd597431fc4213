#!/usr/bin/python3
"""The module dependency graph of src/, read from the #include lines.

  module_graph.py --check          fail (exit 1) on a cycle or on a dependency that
                                   points up the layers below (docs/developer-guide.md §1)
  module_graph.py --dot FILE.dot   write the graph (Graphviz); with --svg FILE.svg also
                                   render it when Graphviz's `dot` is installed

docs/developer-guide.md shows the picture this script draws.
"""
import argparse
import pathlib
import re
import shutil
import subprocess
import sys

# Bottom to top: a module may include modules of its own layer's lower layers only
# (and, within a layer, none of its neighbours).
LAYERS = [
    ["model"],                      # data: nodes, triangles, joints, groups, materials
    ["exec", "law"],                # execution layer; law registries (parameters, state)
    ["io"],                         # file formats and the scenario
    ["fem", "joint", "contact", "seismic", "water", "sph"],  # physics kernels and their phases
    ["boundary", "mesh"],           # boundary set-up, meshing and model building
    ["solver"],                     # the time step
    ["run"],                        # a run end to end: preparation, outputs, restart, stages
    ["ensemble"],                   # many runs: sampling, member processes (MPI), aggregates
    ["app"],                        # the command line
]
INCLUDE = re.compile(r'^\s*#\s*include\s+"([a-z_]+)/', re.M)


def graph(src: pathlib.Path):
    deps = {}
    for folder in sorted(p for p in src.iterdir() if p.is_dir()):
        found = set()
        for f in folder.rglob("*"):
            if f.suffix in (".hpp", ".cpp", ".in"):
                found.update(INCLUDE.findall(f.read_text(errors="replace")))
        found.discard(folder.name)
        deps[folder.name] = sorted(d for d in found if (src / d).is_dir())
    return deps


def layer_of(module):
    for k, layer in enumerate(LAYERS):
        if module in layer:
            return k
    return None


def problems(deps):
    out = []
    for m, ds in deps.items():
        lm = layer_of(m)
        if lm is None:
            out.append(f"module '{m}' is in no layer of scripts/module_graph.py")
            continue
        for d in ds:
            ld = layer_of(d)
            if ld is None or ld >= lm:
                out.append(f"{m} (layer {lm}) includes {d} (layer {ld}): dependencies must point down")
    # Cycles (reported even if the layers were wrong).
    state = {}

    def visit(m, path):
        state[m] = 1
        for d in deps.get(m, []):
            if state.get(d) == 1:
                out.append("cycle: " + " -> ".join(path[path.index(d):] + [d]) if d in path else f"cycle through {d}")
            elif state.get(d) is None:
                visit(d, path + [d])
        state[m] = 2

    for m in deps:
        if state.get(m) is None:
            visit(m, [m])
    return out


def dot(deps):
    lines = ["digraph dsdem {", '  rankdir=BT; node [shape=box, style=rounded, fontname="Helvetica"];']
    for k, layer in enumerate(LAYERS):
        members = " ".join(f'"{m}"' for m in layer if m in deps)
        lines.append(f"  {{ rank=same; {members} }}")
    for m, ds in deps.items():
        for d in ds:
            lines.append(f'  "{m}" -> "{d}";')
    lines.append("}")
    return "\n".join(lines) + "\n"


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--src", default=str(pathlib.Path(__file__).resolve().parent.parent / "src"))
    ap.add_argument("--check", action="store_true")
    ap.add_argument("--dot")
    ap.add_argument("--svg")
    a = ap.parse_args()
    deps = graph(pathlib.Path(a.src))
    if a.dot:
        pathlib.Path(a.dot).write_text(dot(deps))
        if a.svg and shutil.which("dot"):
            subprocess.run(["dot", "-Tsvg", a.dot, "-o", a.svg], check=True)
    if a.check:
        bad = problems(deps)
        for p in bad:
            print(p, file=sys.stderr)
        print(f"{len(deps)} modules, {sum(len(d) for d in deps.values())} dependencies, {len(bad)} problems")
        return 1 if bad else 0
    if not a.dot:
        for m, ds in deps.items():
            print(f"{m}: {' '.join(ds)}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
