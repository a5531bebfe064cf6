"""Beyond one machine (issue 41, docs/distributed.md): a pre-solution table and a dense solve on
1 rank x 1 thread, 1 rank x 2 threads and 2 ranks x 1 thread of this machine, time and peak memory
per rank, with the agreement of every run with the single-process answer.

Runs the `bemsurg` program (table, solve, press) on a generated block held on its base under gravity
(full: 2,048 elements, 6,144 equations; quick: 288 elements), the ranks by mpiexec (one OpenMP and
one BLAS thread per rank). The table's region is the operating region around the top (the same
scene for every configuration); the solve is the dense LU of one process (the reference) and the
"scalapack" method, which splits A* over the ranks.

Data: DIR/distributed/runs.csv (command, method, ranks, threads, equations, columns, seconds (the
command's wall time, mpiexec's start included), peak_mb_max (the largest rank's peak),
peak_mb_per_rank ("a;b"), agreement (max relative difference from the 1 x 1 single-process result:
the press force through the table, or elements.csv's fields)).
"""

import json
import shutil

import numpy as np

import report_lib as rl

NAME = "distributed"
TITLE = "Beyond one machine: tables and the dense solve on MPI ranks"
ORDER = 56

CONFIGS = [(1, 1), (1, 2), (2, 1)]  # (ranks, threads per rank)
COLUMNS = ["command", "method", "ranks", "threads", "equations", "columns", "seconds", "peak_mb_max", "peak_mb_per_rank", "agreement"]
COLOURS = {(1, 1): "tab:blue", (1, 2): "tab:cyan", (2, 1): "tab:orange"}


def _scene(d, method, divisions):
    nx, ny, nz = divisions
    path = d / f"block_{method}.json"
    path.write_text(json.dumps({
        "mesh": {"generator": "box", "min": [-0.05, -0.05, 0], "max": [0.05, 0.05, 0.05], "divisions": [nx, ny, nz]},
        "material": {"young_modulus": 3000, "poisson_ratio": 0.45, "density": 1000}, "gravity": [0, 0, -9.81],
        "boundary_conditions": {"rules": [{"select": {"plane": {"point": [0, 0, 0], "normal": [0, 0, 1]}}, "displacement": [0, 0, 0]}]},
        "operating_region": {"sphere": {"center": [0, 0, 0.05], "radius": 0.02}},
        "solver": {"method": method}}, indent=1))
    return path


def _launcher(ranks):
    mpiexec = shutil.which("mpiexec")
    if ranks == 1:
        return []
    if not mpiexec:
        raise rl.PartFailed("mpiexec not found (scripts/setup-deps.sh installs openmpi-bin)")
    return [mpiexec, "-n", str(ranks), "--allow-run-as-root", "--oversubscribe", "-x", "OMP_NUM_THREADS", "-x", "OPENBLAS_NUM_THREADS"]


def _elements(path):
    rows = rl.read_csv(path)
    return np.array([[r[k] for k in ("ux", "uy", "uz", "tx", "ty", "tz")] for r in rows])


def _agreement(a, b):
    """Max over the columns of max |a - b| / max |b|."""
    scale = np.maximum(np.abs(b).max(axis=0), 1e-300)
    return float((np.abs(a - b).max(axis=0) / scale).max())


def run(ctx):
    d = ctx.part_dir(NAME)
    bemsurg = ctx.program("bemsurg")
    divisions = (6, 6, 3) if ctx.quick else (16, 16, 8)
    scenes = {m: _scene(d, m, divisions) for m in ("lu", "scalapack")}
    # Off the mesh's symmetry lines and with a radius no element centroid sits at, so that round-off
    # (another thread count) cannot move an element in or out of contact: the agreement is the table's.
    press = ["press", scenes["lu"], "--tool", "flat:0.0093", "--at", "0.0011,0.0017,0.05", "--direction", "0,0,-1", "--depth", "0.001",
             "--quiet"]
    rows, reference = [], {}
    runs = [("table", "lu", r, t) for r, t in CONFIGS] + [("solve", "lu", 1, t) for _, t in CONFIGS[:2]]
    runs += [("solve", "scalapack", r, t) for r, t in CONFIGS]
    for command, method, ranks, threads in runs:
        tag = f"{command}_{method}_{ranks}x{threads}"
        out = d / tag
        env = {"OMP_NUM_THREADS": str(threads), "OPENBLAS_NUM_THREADS": str(threads)}
        args = [bemsurg, command, scenes[method], "-o", out, "--quiet"]
        if command == "table":
            args[3:3] = ["--table", d / f"{tag}.tbl"]
        _, seconds = ctx.run(_launcher(ranks) + args, NAME, env=env, timeout=1800)
        report = json.loads((out / "report.json").read_text())
        peaks = report["peak_memory_mb_per_rank"]
        if command == "table":
            ctx.run([bemsurg] + press + ["--table", d / f"{tag}.tbl", "-o", d / f"press_{tag}"], NAME, timeout=600)
            force = json.loads((d / f"press_{tag}" / "force.json").read_text())
            if not force["table"]["loaded_from_file"]:
                raise rl.PartFailed(f"press recomputed the table {tag}.tbl instead of reading it")
            value = np.array([force["force"]])
            columns = report["columns"]
        else:
            value = _elements(out / "elements.csv")
            columns = 1
        reference.setdefault(command, value)  # the first run of a command: 1 rank x 1 thread, single process
        rows.append({"command": command, "method": method, "ranks": ranks, "threads": threads, "equations": report["equations"],
                     "columns": columns, "seconds": seconds, "peak_mb_max": max(peaks),
                     "peak_mb_per_rank": ";".join(f"{p:.1f}" for p in peaks),
                     "agreement": _agreement(value, reference[command])})
    rl.write_csv(d / "runs.csv", rows, COLUMNS)


def _label(r):
    what = "table" if r["command"] == "table" else ("solve, dense LU" if r["method"] == "lu" else "solve, scalapack")
    return what


def _chart(ctx, rows):
    groups = []
    for r in rows:
        if _label(r) not in groups:
            groups.append(_label(r))
    fig, (ax_t, ax_m) = rl.plt.subplots(1, 2, figsize=(10.0, 4.2), dpi=110)
    width = 0.26
    x = np.arange(len(groups))
    for j, cfg in enumerate(CONFIGS):
        t, m = [], []
        for g in groups:
            r = next((r for r in rows if _label(r) == g and (r["ranks"], r["threads"]) == cfg), None)
            t.append(r["seconds"] if r else np.nan)
            m.append(r["peak_mb_max"] if r else np.nan)
        label = f"{cfg[0]} rank{'s' if cfg[0] > 1 else ''} x {cfg[1]} thread{'s' if cfg[1] > 1 else ''}"
        for ax, values in ((ax_t, t), (ax_m, m)):
            ax.bar(x - width + j * width, values, width, label=label, color=COLOURS[cfg], edgecolor="black", linewidth=0.4)
    for ax, ylabel in ((ax_t, "seconds (the command's wall time)"), (ax_m, "peak memory of the largest rank (MiB)")):
        ax.set_xticks(x)
        ax.set_xticklabels(groups, fontsize=8)
        ax.set_ylabel(ylabel)
        ax.grid(True, axis="y", alpha=0.3)
    ax_t.legend(fontsize=7)
    n = rows[0]["equations"] if rows else 0
    fig.suptitle(f"{n} equations on this machine: time and memory per rank", fontsize=9)
    rl.save(fig, ctx.image("distributed_ranks"))


def _table(rows, base):
    lines = ["| run | ranks x threads | seconds | / 1 x 1 | peak MiB per rank | largest / 1 x 1 dense | agreement with 1 x 1 |",
             "|---|---|---|---|---|---|---|"]
    for r in rows:
        b = base.get(r["command"])
        dense = base.get("solve") if r["command"] == "solve" else b
        lines.append(f"| {_label(r)} | {r['ranks']} x {r['threads']} | {rl.seconds_text(r['seconds'])} | "
                     f"{r['seconds'] / b['seconds']:.2f} | {str(r['peak_mb_per_rank']).replace(';', ', ')} | "
                     f"{r['peak_mb_max'] / dense['peak_mb_max']:.2f} | {r['agreement']:.1e} |")
    return "\n".join(lines)


def render(ctx):
    rows = rl.read_csv(ctx.part_dir(NAME) / "runs.csv")
    if not rows:
        return "No runs (the part did not run)."
    base = {}
    for r in rows:
        base.setdefault(r["command"], r)  # 1 x 1, single process: the table, and the dense LU solve
    _chart(ctx, rows)
    n, cols = rows[0]["equations"], next((r["columns"] for r in rows if r["command"] == "table"), 0)
    intro = (f"A block held on its base under gravity, {n} equations; the table has {cols} columns (the operating region "
             "around the top). *1 rank x 2 threads* is one process on both cores (OpenMP assembly, OpenBLAS LU); *2 ranks x 1 "
             "thread* is mpiexec with one thread per rank. A table's ranks each hold the factorisation and share the columns; "
             "the scalapack solve splits A* over the ranks (docs/distributed.md). Seconds are the command's wall time, "
             "mpiexec's start included; memory is each rank's peak resident set. Agreement: max relative difference from the "
             "single-process answer of the same run (the press force through the table, or every element's displacement and "
             "traction).")
    split = [r for r in rows if r["method"] == "scalapack" and r["ranks"] > 1]
    text = []
    if split and "solve" in base:
        r = split[0]
        text.append(f"On {r['ranks']} ranks the scalapack solve's largest rank peaks at {r['peak_mb_max'] / base['solve']['peak_mb_max']:.2f} "
                    f"of the single-process dense solve's memory and takes {r['seconds'] / base['solve']['seconds']:.2f} of its time, "
                    f"agreeing to {r['agreement']:.1e}.")
    tables = [r for r in rows if r["command"] == "table" and r["ranks"] > 1]
    if tables:
        r = tables[0]
        text.append(f"The table on {r['ranks']} ranks takes {r['seconds'] / base['table']['seconds']:.2f} of one rank's time: "
                    "each rank repeats the assembly and the factorisation, so on one machine the ranks only share the column solves; "
                    "across nodes each rank has a node's cores for its own factorisation.")
    return "\n\n".join([intro, "![time and memory per rank](images/distributed_ranks.png)", _table(rows, base), " ".join(text)])
