"""Accuracy against cost (issue 24, item 2): work-precision diagrams.

run() asks each program of PROGRAMS for its configurations (``--list``, with ``--quick`` in quick
mode), runs every one in a process of its own (peak resident memory from wait4 belongs to that
configuration alone) and writes accuracy/work_precision.csv. render() draws, per problem, the
relative L2 errors of u and t against total time and against peak memory (one series per study
variant, Pareto front marked), the cheapest configuration reaching 10 %, 5 % and 1 %, and a
paragraph computed from the CSV: observed convergence order of the mesh levels, and what the
quadrature, solver and mesh variants gain or lose against the baseline of the same mesh.
"""

import json
import shlex

import report_lib as rl

NAME = "accuracy"
TITLE = "Accuracy against cost"
ORDER = 10

PROGRAMS = ("bench_work_precision", "bench_contact_accuracy")
PARAMS = ["program", "problem", "study", "level", "quadrature", "solver", "tolerance", "mesh", "element_type", "feed"]
METRICS = ["elements", "equations", "mean_h", "error_u", "error_t", "assembly_s", "factor_s", "solve_s", "total_s",
           "iterations", "status", "peak_rss_bytes", "wall_s", "peak_hwm_bytes", "total_min_s", "total_max_s", "runs"]
# Spread (issue 37): each configuration runs in RUNS processes, or as many as fit in RUN_BUDGET_S
# seconds of its own time (at least one); the times are the medians over the runs, total_min_s and
# total_max_s their range, `runs` their count. The errors are the first run's (a direct solve gives
# the same answer every time; the runs' errors are checked to agree).
RUNS = 5
RUN_BUDGET_S = 40.0
COLUMNS = PARAMS + METRICS
ERRORS = (("error_u", "displacement u"), ("error_t", "traction t"))
BASELINE = {"quadrature": "baseline", "solver": "lu", "mesh": "uniform", "element_type": "constant"}
# wait4's (and getrusage's) ru_maxrss holds the driver's own resident size at fork as a floor (Linux
# keeps it across exec: about 60 MiB of Python and matplotlib here), so the charts use the program's
# VmHWM (peak_hwm_bytes: its image's own peak) where it reports one, and wait4's figure otherwise.
MEMORY_NOTE = ("Memory: the peak resident size of the configuration's process (VmHWM; wait4's ru_maxrss, also in the "
               "CSV, cannot go below the driver's own size at fork).")
TIMEOUT_S = 900  # one configuration; the largest full-mode ones take tens of seconds


# ---- run --------------------------------------------------------------------------------------
def _run_program(ctx, program, raw_dir):
    """Rows of every configuration `program` lists, and the failures as text."""
    exe = ctx.program(program)
    listing, _ = ctx.run([exe, "--list"] + (["--quick"] if ctx.quick else []), NAME)
    rows, failures = [], []
    for i, line in enumerate(l for l in listing.splitlines() if l.strip()):
        args = shlex.split(line)
        path = raw_dir / f"{program}-{i:03d}.json"
        row = {"program": program}
        row.update({args[k][2:]: args[k + 1] for k in range(0, len(args) - 1, 2) if args[k].startswith("--")})
        runs, spent = [], 0.0
        try:
            while len(runs) < (1 if ctx.quick else RUNS) and (not runs or spent < RUN_BUDGET_S):
                once = ["--repeats", "1"] if program == "bench_work_precision" else []  # the runs are the processes
                _, wall, rss = ctx.run_isolated([exe] + args + once + ["--json", str(path)], NAME, timeout=TIMEOUT_S)
                runs.append((json.loads(path.read_text()), wall, rss))
                spent += wall
        except rl.PartFailed as e:
            failures.append(str(e).splitlines()[0])
            row["status"] = "error"
            rows.append(row)
            continue
        result = runs[0][0]
        row.update({k: result[k] for k in COLUMNS if k in result and k not in ("program", "peak_rss_bytes", "wall_s")})
        for key in ("assembly_s", "factor_s", "solve_s", "total_s"):
            vals = [r[key] for r, _, _ in runs if isinstance(r.get(key), (int, float))]
            if vals:
                row[key] = rl.median(vals)
        totals = [r["total_s"] for r, _, _ in runs if isinstance(r.get("total_s"), (int, float))]
        if totals:
            row["total_min_s"], row["total_max_s"] = min(totals), max(totals)
        row["runs"] = len(runs)
        # A direct solve gives the same errors in every process; a Krylov one may stop an iteration
        # earlier or later (threaded sums), so its errors may differ by about its tolerance.
        tol = max(1e-3, 10.0 * float(row.get("tolerance") or 0.0))
        for key in ("error_u", "error_t"):
            vals = [r.get(key) for r, _, _ in runs if isinstance(r.get(key), (int, float))]
            if vals and max(vals) > (1.0 + tol) * min(vals) + 1e-15:
                failures.append(f"{' '.join(args)}: {key} differs between runs ({min(vals):.6g} to {max(vals):.6g})")
        row["peak_rss_bytes"] = max(rss for _, _, rss in runs)
        row["wall_s"] = rl.median([w for _, w, _ in runs])
        row["peak_hwm_bytes"] = max((r.get("peak_hwm_bytes") or 0) for r, _, _ in runs) or None
        rows.append(row)
    return rows, failures


def run(ctx):
    out = ctx.part_dir(NAME)
    raw = out / "raw"
    raw.mkdir(exist_ok=True)
    rows, failures, programs = [], [], []
    for program in PROGRAMS:
        if not (ctx.bin / program).exists():
            programs.append({"program": program, "status": "missing", "configurations": 0})
            continue
        r, f = _run_program(ctx, program, raw)
        rows += r
        failures += f
        programs.append({"program": program, "status": "ran", "configurations": len(r)})
    rl.write_csv(out / "work_precision.csv", rows, COLUMNS)
    rl.write_csv(out / "programs.csv", programs, ["program", "status", "configurations"])
    if failures:
        raise rl.PartFailed(f"{len(failures)} configuration(s) failed, first: {failures[0]}")


# ---- render helpers -----------------------------------------------------------------------------
FAILED = ("failed", "error", "iteration_limit", "breakdown", "stagnation", "non_finite", "not_computed")


def _ok(r):
    return r.get("status") not in FAILED and r.get("total_s")


def _bytes(b):
    return f"{b / 2**30:.3g} GiB" if b and b >= 2**30 else rl.bytes_text(b)


def _label(r):
    """The series a row belongs to: the mesh levels, or the one factor its study changes."""
    study = r.get("study")
    if study == "levels":
        mesh = r.get("mesh") or "uniform"
        return "mesh levels (baseline)" if mesh == "uniform" else f"mesh levels ({mesh} baseline)"
    if study == "quadrature":
        return f"quadrature {r.get('quadrature')}"
    if study == "solver":
        return f"{r.get('solver')} tol {r.get('tolerance'):g}" if r.get("tolerance") else str(r.get("solver"))
    if study == "mesh":
        return f"mesh {r.get('mesh')}"
    if study == "hmatrix":
        return f"hierarchical (hmatrix tol {r.get('tolerance'):g})"
    if study == "elements":
        feed = r.get("feed")
        return f"{r.get('element_type')} elements" + (f", fed at the {feed}" if feed else "")
    changed = [f"{k} {r.get(k)}" for k, v in BASELINE.items() if r.get(k) not in (None, v)]
    return f"{study}: " + (", ".join(changed) or "baseline")


# One colour per family of series (issue 37: legends grouped by family, a fixed colour each), the
# members of a family told apart by marker and shade.
FAMILY_COLOURS = {"levels": "#222222", "quadrature": "#2ca02c", "gmres": "#1f77b4", "bicgstab": "#ff7f0e",
                  "elements": "#d62728", "mesh": "#9467bd", "hmatrix": "#17becf"}


def _family(label):
    if label.startswith("mesh levels"):
        return "levels"
    for f in ("quadrature", "gmres", "bicgstab", "hmatrix", "elements", "mesh"):
        if f in label:
            return f
    return "other"


def _style_factory():
    seen = {}

    def style(label):
        fam = _family(label)
        k = seen.setdefault(fam, {}).setdefault(label, len(seen[fam]))
        colour = FAMILY_COLOURS.get(fam, "#7f7f7f")
        return {"color": colour, "marker": rl.MARKERS[k % len(rl.MARKERS)], "alpha": max(0.45, 1.0 - 0.15 * k)}
    return style


def _time_range(r):
    return (r.get("total_min_s"), r.get("total_max_s")) if (r.get("runs") or 0) > 1 else None


def _time_text(r):
    return rl.spread_text(r.get("total_s"), r.get("total_min_s"), r.get("total_max_s"), r.get("runs"))


def _memory(r):
    hwm = r.get("peak_hwm_bytes")
    return hwm if hwm and hwm > 0 else r.get("peak_rss_bytes")


def _describe(r):
    return f"{_label(r)}, level {r.get('level')} ({r.get('elements')} el.)"


def _series(rows, error_key, cost_key, scale=1.0):
    series = {}
    for r in sorted(rows, key=lambda r: (r.get("level") or 0, r.get("elements") or 0)):
        if _ok(r) and r.get(error_key) and r.get(cost_key):
            cost = _memory(r) if cost_key == "peak_rss_bytes" else r[cost_key]
            series.setdefault(_label(r), []).append((cost * scale, r[error_key], r))
    return series


def _figure(ctx, problem, rows, cost_key, cost_label, scale, name, title=None):
    keys = [(k, t) for k, t in ERRORS if any(_ok(r) and r.get(k) for r in rows)]
    if not keys:
        return None
    fig, axes = rl.plt.subplots(1, len(keys), figsize=(7.6 * len(keys), 4.8), dpi=110, squeeze=False)
    style = _style_factory()
    for ax, (key, text) in zip(axes[0], keys):
        ax.grid(True, which="both", alpha=0.3)
        rng = _time_range if cost_key == "total_s" else None
        rl.work_precision(ax, _series(rows, key, cost_key, scale), cost_label, f"relative L2 error of {text}",
                          cost_range=rng, style=style)
        ax.set_title(f"{title or problem}: error of {text} against {cost_label.split(' (')[0]}", fontsize=9)
    fig.tight_layout()
    rl.save(fig, ctx.image(name))
    return f"![{problem}: error against {cost_label}](images/{name}.png)"


def _reference(rows, r):
    """The baseline run of r's mesh: a baseline row of r's own study, else the levels row."""
    same = [q for q in rows if _ok(q) and q.get("level") == r.get("level") and q is not r
            and all(q.get(k) == v for k, v in BASELINE.items())]
    own = [q for q in same if q.get("study") == r.get("study")]
    lev = [q for q in same if q.get("study") == "levels"]
    return (own or lev or [None])[0]


def _ratio(a, b):
    return a / b if a and b else None


def _order_text(rows):
    lev = [r for r in rows if _ok(r) and r.get("study") == "levels" and r.get("mean_h")]
    if len(lev) < 2:
        return ""
    parts = []
    for key, text in ERRORS:
        pts = [r for r in lev if r.get(key)]
        p = rl.fit_exponent([r["mean_h"] for r in pts], [r[key] for r in pts])
        if p is not None:
            parts.append(f"{key[-1]} {p:.2f}")
    if not parts:
        return ""
    fine = max(lev, key=lambda r: r["elements"])
    errs = ", ".join(f"{k[-1]} {fine[k]:.2%}" for k, _ in ERRORS if fine.get(k))
    return (f"Observed order over the mesh levels (least-squares slope of log error on log mean h, "
            f"{min(r['elements'] for r in lev)}–{fine['elements']} elements): {', '.join(parts)}. "
            f"The finest level gives {errs} in {_time_text(fine)} and {_bytes(_memory(fine))}.")


def _times(x):
    return f"{x:.3g}× faster" if x >= 1 else f"{1 / x:.3g}× slower"


def _compare(r, ref):
    """'1.2× faster (solve phase 5× faster, 3 it.), errors u ×1.00 t ×1.30' against ref."""
    text = _times(ref["total_s"] / r["total_s"])
    if r.get("study") == "solver":
        ps = _ratio((ref.get("factor_s") or 0) + (ref.get("solve_s") or 0), (r.get("factor_s") or 0) + (r.get("solve_s") or 0))
        if ps:
            text += f" (factor + solve {_times(ps)}, {r.get('iterations')} it.)"
    errs = [f"{k[-1]} ×{_ratio(r.get(k), ref.get(k)):.2f}" for k, _ in ERRORS if _ratio(r.get(k), ref.get(k))]
    return text + (", error " + " ".join(errs) if errs else "")


def _variant_notes(rows):
    """One line per variant group at its largest level: time and error ratios against the
    baseline run of the same mesh (solver: one line per method, its tolerances in turn)."""
    groups = {}
    for r in rows:
        if not _ok(r) or r.get("study") == "levels" or all(r.get(k) == v for k, v in BASELINE.items()):
            continue
        ref = _reference(rows, r)
        if ref:
            key = (r.get("study"), r.get("solver") if r.get("study") == "solver" else _label(r))
            groups.setdefault(key, []).append((r, ref))
    notes = []
    for (study, name), pairs in groups.items():
        top = max(p[0].get("elements") or 0 for p in pairs)
        pairs = sorted([p for p in pairs if (p[0].get("elements") or 0) == top], key=lambda p: -(p[0].get("tolerance") or 0))
        r0, ref = pairs[0]
        own = "" if ref.get("elements") == top else f" ({top} el.)"
        head = (f"{name if study == 'solver' else _label(r0)}{own} against the baseline run of level {r0.get('level')} "
                f"({ref.get('elements')} el.): ")
        if study == "solver":
            notes.append(head + "; ".join(f"tol {r.get('tolerance'):g}: {_compare(r, ref)}" for r, ref in pairs) + ".")
        else:
            notes.append(head + _compare(r0, ref) + ".")
    return notes


def _miss_text(rows):
    misses = []
    for key, _ in ERRORS:
        vals = [r[key] for r in rows if _ok(r) and r.get(key)]
        if vals and min(vals) > rl.THRESHOLDS[-1]:
            misses.append(f"no configuration reaches {rl.THRESHOLDS[-1]:.0%} in {key[-1]} (best {min(vals):.2%})")
    return ("**Target missed:** " + "; ".join(misses) + ".") if misses else ""


MESH_STUDY_TEXT = ("The graded-against-uniform study solves **another problem** than the levels above: a block of "
                   "L/a = 6, whose truncation floor (about 10 % in the force, 30 % in error_u; bench_contact_accuracy.cpp) "
                   "both meshes share, so it compares cost at equal error and is drawn apart from the levels' front.")


def _mesh_study(ctx, problem, rows):
    """The graded-against-uniform study of a contact problem, on its own chart and lines."""
    slug = "".join(c if c.isalnum() else "_" for c in str(problem))
    lines = [f"#### {problem}: graded against uniform (its own block)", "", MESH_STUDY_TEXT, ""]
    img = _figure(ctx, problem, rows, "total_s", "total time (s)", 1.0, f"accuracy_{slug}_mesh_study",
                  title=f"{problem}, L/a = 6")
    if img:
        lines += [img, ""]
    lines += ["| level | mesh | elements | error u | error t | total time |", "|---|---|---|---|---|---|"]
    for r in sorted(rows, key=lambda r: (r.get("level") or 0, r.get("mesh") or "")):
        eu, et = r.get("error_u"), r.get("error_t")
        lines.append(f"| {r.get('level')} | {r.get('mesh')} | {r.get('elements')} | {'–' if eu is None else f'{eu:.2%}'} | "
                     f"{'–' if et is None else f'{et:.2%}'} | {_time_text(r) if _ok(r) else r.get('status')} |")
    return lines + [""]


def _section(ctx, problem, rows):
    side = [r for r in rows if r.get("study") == "mesh"]
    rows = [r for r in rows if r.get("study") != "mesh"]
    lines = [f"### {problem}", ""]
    text = " ".join(t for t in [_order_text(rows), _miss_text(rows)] if t)
    if text:
        lines += [text, ""]
    notes = _variant_notes(rows)
    if notes:
        lines += ["- " + n for n in notes] + [""]
    slug = "".join(c if c.isalnum() else "_" for c in str(problem))
    for img in (_figure(ctx, problem, rows, "total_s", "total time (s)", 1.0, f"accuracy_{slug}_time"),
                _figure(ctx, problem, rows, "peak_rss_bytes", "peak resident memory (MiB)", 2.0 ** -20, f"accuracy_{slug}_memory")):
        if img:
            lines += [img, ""]
    costs = {"total_s": ("total time (median, min–max)", _time_text, True), "memory": ("peak memory", _bytes)}
    ok = [dict(r, memory=_memory(r)) for r in rows if _ok(r)]
    for key, text in ERRORS:
        if any(r.get(key) for r in ok):
            lines += [f"Cheapest in time reaching each error of {text}:", "", rl.cheapest_table(ok, key, costs, _describe), ""]
    failed = [r for r in rows if not _ok(r)]
    if failed:
        lines += [f"Not converged or failed ({len(failed)}): " + "; ".join(f"{_describe(r)}: {r.get('status')}" for r in failed), ""]
    few = [r for r in rows if _ok(r) and (r.get("runs") or 1) < RUNS]
    if ctx.quick:
        lines += ["Times: one run each (quick mode).", ""]
    elif few:
        lines += [f"Times: medians of {RUNS} runs with the min–max as horizontal bars, except {len(few)} configuration(s) "
                  f"whose runs exceeded {RUN_BUDGET_S:.0f} s first: " +
                  "; ".join(f"{_describe(r)} {_time_text(r)}" for r in few) + ".", ""]
    if side:
        lines += _mesh_study(ctx, problem, side)
    return lines


# ---- render -----------------------------------------------------------------------------------
def render(ctx):
    d = ctx.part_dir(NAME)
    rows = rl.read_csv(d / "work_precision.csv")
    for r in rows:  # programs and runs before issue 27 have constant elements only
        if not r.get("element_type"):
            r["element_type"] = "constant"
    programs = rl.read_csv(d / "programs.csv") if (d / "programs.csv").exists() else []
    lines = ["Relative L2 errors of the solved boundary values (u where traction is prescribed, t where u is) "
             "against closed forms, versus total time (assembly + factorisation or preconditioner + solve) and the "
             "peak resident memory of a process that ran that configuration alone. Series: the mesh levels at the "
             "baseline (default quadrature, dense LU; a uniform mesh, graded towards the tool for the contact problems, "
             "as their series' name says), and one factor changed at a time, each family in its own colour; the grey "
             "step line is the Pareto front. Times are medians of up to %d runs of the configuration's process, the "
             "bars their min–max. Linear elements are fed the exact field at their collocation nodes (the node form of "
             "bc.csv) or at their corners, interpolated to the nodes (the corner form; docs/elements.md), one front "
             "each; errors are measured where each element type collocates. " % RUNS + MEMORY_NOTE, ""]
    missing = [p["program"] for p in programs if p.get("status") == "missing"]
    if missing:
        lines += ["*Not built, skipped:* " + ", ".join(f"`{m}`" for m in missing) + ".", ""]
    problems = []
    for r in rows:
        if r.get("problem") not in problems:
            problems.append(r.get("problem"))
    for p in problems:
        lines += _section(ctx, p, [r for r in rows if r.get("problem") == p])
    if not rows:
        lines.append("No configuration ran.")
    return "\n".join(lines)
