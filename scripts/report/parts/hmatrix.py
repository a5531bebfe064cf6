"""Hierarchical matrices against dense (issue 40, item 5; docs/solvers.md "Hierarchical matrices"):
bench_hmatrix's cube resting under gravity, solved at each size by the hierarchical backend (hmat-oss,
ACA+ at the series' tolerance, H-LU) and by dense LU in the same process, each with its own peak
memory; then the hierarchical solve at one size over a sweep of compression tolerances.

CSV hmatrix_sizes.csv, one row per size: elements, equations, dense_s, hierarchical_s, time_ratio
(hierarchical / dense), dense_peak_mb, hierarchical_peak_mb, memory_ratio, compression_ratio (stored
/ dense entries of A*), largest_rank, displacement_difference and traction_difference (max |h − d| /
max |d|); hmatrix_linear_sizes.csv the same for the linear-element series (9 unknowns per element).
CSV hmatrix_sweep.csv, one row per tolerance: tolerance, compression_ratio, largest_rank,
seconds, displacement_difference, traction_difference, relative_residual. CSV hmatrix_cuts.csv, one
row per size of the cut study (docs/cutting.md "On either backend": a table kept for cuts on each
backend, the same exact cut steps): elements, region_elements, steps, dense_step_s and
hierarchical_step_s (medians over the steps), step_ratio, dense_precompute_s, hierarchical_precompute_s,
dense_factor_mb, hierarchical_factor_mb, columns_difference and base_difference (the final tables, max
|h − d| / max |d|). hmatrix.json: the fitted time exponents and the crossovers bench_hmatrix interpolated,
for constant and for linear elements.
"""

import json

import numpy as np

import report_lib as rl

NAME = "hmatrix"
TITLE = "Hierarchical matrices against dense"
ORDER = 55

SIZE_COLUMNS = ["elements", "equations", "dense_s", "hierarchical_s", "time_ratio", "dense_peak_mb", "hierarchical_peak_mb",
                "memory_ratio", "compression_ratio", "largest_rank", "displacement_difference", "traction_difference"]
CUT_COLUMNS = ["elements", "region_elements", "steps", "dense_step_s", "hierarchical_step_s", "step_ratio", "dense_precompute_s",
               "hierarchical_precompute_s", "dense_factor_mb", "hierarchical_factor_mb", "columns_difference", "base_difference"]
SWEEP_COLUMNS = ["tolerance", "compression_ratio", "largest_rank", "seconds", "displacement_difference", "traction_difference",
                 "relative_residual"]


def run(ctx):
    d = ctx.part_dir(NAME)
    raw = d / "bench_hmatrix.json"
    args = [ctx.program("bench_hmatrix"), "--json", raw] + (["--quick"] if ctx.quick else [])
    ctx.run(args, NAME, timeout=3600)
    j = json.loads(raw.read_text())
    summary = {k: j.get(k) for k in ("available", "tolerance", "time_exponent", "crossover_elements", "memory_crossover_elements",
                                     "linear_time_exponent", "linear_crossover_elements", "linear_memory_crossover_elements",
                                     "body", "peak_memory_resets")}
    summary["sweep_elements"] = j.get("sweep", {}).get("elements")
    (d / "hmatrix.json").write_text(json.dumps(summary, indent=2) + "\n")
    if not j.get("available"):
        return
    for key, name in (("sizes", "hmatrix_sizes.csv"), ("linear_sizes", "hmatrix_linear_sizes.csv")):
        rows = [{"elements": s["elements"], "equations": s["equations"], "dense_s": s["dense_seconds"],
                 "hierarchical_s": s["hierarchical_seconds"], "time_ratio": s["time_ratio"], "dense_peak_mb": s["dense_peak_mb"],
                 "hierarchical_peak_mb": s["hierarchical_peak_mb"], "memory_ratio": s["memory_ratio"],
                 "compression_ratio": s["compression_ratio"], "largest_rank": s["largest_rank"],
                 "displacement_difference": s["displacement_difference"], "traction_difference": s["traction_difference"]}
                for s in j.get(key, [])]
        if rows:
            rl.write_csv(d / name, rows, SIZE_COLUMNS)
    rl.write_csv(d / "hmatrix_sweep.csv", j["sweep"]["rows"], SWEEP_COLUMNS)
    cuts = [{"elements": c["elements"], "region_elements": c["region_elements"], "steps": c["steps"],
             "dense_step_s": c["dense_step_median_seconds"], "hierarchical_step_s": c["hierarchical_step_median_seconds"],
             "step_ratio": c["step_time_ratio"], "dense_precompute_s": c["dense_precompute_seconds"],
             "hierarchical_precompute_s": c["hierarchical_precompute_seconds"], "dense_factor_mb": c["dense_factor_mb"],
             "hierarchical_factor_mb": c["hierarchical_factor_mb"], "columns_difference": c["columns_difference"],
             "base_difference": c["base_displacement_difference"]} for c in j.get("cuts", [])]
    rl.write_csv(d / "hmatrix_cuts.csv", cuts, CUT_COLUMNS)


def _floored(rows):
    """The peaks of a size series that read the process's resident floor rather than the solve's own
    peak: the high-water mark can only be reset to what the process still holds, so a series run after
    larger solves (the linear one, after the constant one) reads that floor wherever its own peak was
    lower. Such a value is the series' smallest peak, repeated (both backends at a size, or several
    sizes). Returns {(row index, key)} of the floored cells."""
    keys = ("dense_peak_mb", "hierarchical_peak_mb")
    values = [r[k] for r in rows for k in keys if r.get(k)]
    if len(values) < 2:
        return set()
    floor = min(values)
    at_floor = {(i, k) for i, r in enumerate(rows) for k in keys if r.get(k) and r[k] <= floor * 1.005}
    return at_floor if len(at_floor) >= 2 else set()


def _exp(p):
    return "–" if p is None else f"{p:.2f}"


def _size_chart(ctx, rows, crossover, linear_rows=(), linear_crossover=None):
    """Time and memory against n: constant elements solid, linear ones dashed (same colours per backend)."""
    fig, (ax_t, ax_m) = _two_axes()
    for series, kind, style in ((rows, "constant", "-"), (linear_rows, "linear", "--")):
        if not series:
            continue
        ns = [r["equations"] for r in series]
        for ax, keys in ((ax_t, (("dense_s", "dense LU", "s", "black"), ("hierarchical_s", "hierarchical (H-LU)", "o", "C0"))),
                         (ax_m, (("dense_peak_mb", "dense LU", "s", "black"), ("hierarchical_peak_mb", "hierarchical", "o", "C0")))):
            floored = _floored(series) if ax is ax_m else set()
            for key, label, marker, colour in keys:
                ys = [np.nan if (i, key) in floored else r[key] for i, r in enumerate(series)]
                ax.plot(ns, ys, marker=marker, color=colour, linestyle=style,
                        label=f"{label}, {kind}: n^{_exp(rl.fit_exponent(ns, ys))}")
    if crossover:
        ax_t.axvline(3.0 * crossover, color="grey", linestyle=":", label=f"crossover ≈ {crossover:,.0f} constant elements")
    if linear_crossover:
        ax_t.axvline(9.0 * linear_crossover, color="grey", linestyle="-.",
                     label=f"crossover ≈ {linear_crossover:,.0f} linear elements")
    for ax, ylabel, title in ((ax_t, "whole solve (s)", "time"), (ax_m, "peak resident memory (MB)", "memory")):
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel("equations n (3 per constant element, 9 per linear one)")
        ax.set_ylabel(ylabel)
        ax.set_title(f"{title} against n, both backends")
        ax.legend(fontsize=7, title="fitted exponent p of y ≈ c·n^p", title_fontsize=7)
    rl.save(fig, ctx.image("hmatrix_vs_n"))


def _two_axes():
    fig, ax = rl.new_figure(11.0, 4.4)
    fig.delaxes(ax)
    axes = fig.subplots(1, 2)
    for a in axes:
        a.grid(True, which="both", alpha=0.3)
    return fig, axes


def _sweep_chart(ctx, sweep, elements):
    fig, ax = rl.new_figure(6.4, 4.4)
    ts = [r["tolerance"] for r in sweep]
    ax.plot(ts, [r["displacement_difference"] for r in sweep], marker="o", label="displacement: max |h − d| / max |d|")
    ax.plot(ts, [r["traction_difference"] for r in sweep], marker="^", label="traction: max |h − d| / max |d|")
    ax.plot(ts, [r["compression_ratio"] for r in sweep], marker="s", color="black", label="stored / dense entries of A*")
    ax.plot(ts, ts, linestyle=":", color="grey", label="y = tolerance")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.invert_xaxis()
    ax.set_xlabel("ACA+ compression tolerance (tighter →)")
    ax.set_ylabel("difference from dense LU; stored fraction")
    ax.set_title(f"Compression and added error against tolerance ({elements} elements)")
    ax.legend(fontsize=7)
    rl.save(fig, ctx.image("hmatrix_tolerance"))


def _crossover_text(summary, rows):
    x, xm = summary.get("crossover_elements"), summary.get("memory_crossover_elements")
    big = rows[-1]
    out = []
    if x is None:
        out.append(f"Within the sizes run (up to {big['elements']:,} elements) the hierarchical solve is not faster than dense LU: "
                   f"at the largest it takes {big['time_ratio']:.2f}× the dense time.")
    else:
        out.append(f"The hierarchical solve becomes faster than dense LU at about **{x:,.0f} elements** (interpolated, log-log, "
                   f"between the sizes on either side); at {big['elements']:,} elements it takes {big['time_ratio']:.2f}× the dense "
                   f"time.")
    if xm is not None:
        out.append(f"It needs less peak memory from about {xm:,.0f} elements on; at {big['elements']:,} it needs "
                   f"{big['memory_ratio']:.2f}× the dense peak ({big['hierarchical_peak_mb']:,.0f} against "
                   f"{big['dense_peak_mb']:,.0f} MB), storing {big['compression_ratio']:.3f} of dense A*'s entries.")
    small = rows[0]
    out.append(f"At the fixed per-block tolerance {summary.get('tolerance')} the difference from dense LU grows with n: displacement "
               f"{small['displacement_difference']:.1e} at {small['elements']:,} elements, {big['displacement_difference']:.1e} at "
               f"{big['elements']:,}; traction {small['traction_difference']:.1e} and {big['traction_difference']:.1e} (relative "
               "to the largest entry of each field). A large mesh that needs dense LU's digits needs a tighter tolerance (the sweep below).")
    return " ".join(out)


def render(ctx):
    d = ctx.part_dir(NAME)
    summary = json.loads((d / "hmatrix.json").read_text())
    if not summary.get("available"):
        return "bench_hmatrix ran on a build without hmat-oss (libhmat-oss-dev): nothing was measured."
    rows = sorted(rl.read_csv(d / "hmatrix_sizes.csv"), key=lambda r: r["equations"])
    sweep = rl.read_csv(d / "hmatrix_sweep.csv")
    linear_csv = d / "hmatrix_linear_sizes.csv"
    linear_rows = sorted(rl.read_csv(linear_csv), key=lambda r: r["equations"]) if linear_csv.exists() else []
    _size_chart(ctx, rows, summary.get("crossover_elements"), linear_rows, summary.get("linear_crossover_elements"))
    _sweep_chart(ctx, sweep, summary.get("sweep_elements"))
    lines = [
        f"`bench_hmatrix`: {summary.get('body')}, solved at each size by the hierarchical backend (hmat-oss: ACA+ at "
        f"{summary.get('tolerance')}, standard admissibility η = 2, leaves of 120 unknowns, H-LU; docs/solvers.md) and by dense "
        "LU, in the same process, hierarchical first. Time: the whole solve (assembly, factorisation, solve), one run per size. "
        "Memory: each solve's own peak resident set (the kernel's high-water mark reset before it), so both include the "
        "process's baseline of some tens of MB. The legends give exponents fitted over all sizes.",
        "", "![time and memory against n](images/hmatrix_vs_n.png)", "",
        *_size_table(rows)]
    lines += ["", _crossover_text(summary, rows)]
    if linear_rows:
        lines += ["", "Linear elements (dashed in the chart; 9 unknowns per element, their rows at the nodes):", "",
                  *_size_table(linear_rows)]
        lx = summary.get("linear_crossover_elements")
        lines += ["", (f"With linear elements the hierarchical solve becomes faster at about **{lx:,.0f} elements** "
                       f"(n ≈ {9 * lx:,.0f}); method auto's threshold counts unknowns, so it applies to both element types."
                       if lx else f"With linear elements the hierarchical solve is not faster within the sizes run (up to "
                       f"{linear_rows[-1]['elements']:,} elements: {linear_rows[-1]['time_ratio']:.2f}× the dense time).")]
    lines += ["",
              "The tolerance sweep: the same solve at one size, ACA+'s tolerance from loose to tight. The difference from "
              "dense LU falls with the tolerance while the stored fraction rises." + (
                  " Below some tolerance the low-rank blocks store more than the dense blocks they replace (a stored "
                  "fraction above 1)." if any(r["compression_ratio"] > 1.0 for r in sweep) else ""),
              "", "![compression and error against tolerance](images/hmatrix_tolerance.png)", "",
              "| tolerance | stored / dense | largest rank | time | displacement diff. | traction diff. | residual |",
              "|---|---|---|---|---|---|---|"]
    for r in sweep:
        lines.append(f"| {r['tolerance']:.0e} | {r['compression_ratio']:.3f} | {r['largest_rank']} | {rl.seconds_text(r['seconds'])} | "
                     f"{r['displacement_difference']:.1e} | {r['traction_difference']:.1e} | {r['relative_residual']:.1e} |")
    cuts_csv = d / "hmatrix_cuts.csv"
    if cuts_csv.exists():
        cuts = sorted(rl.read_csv(cuts_csv), key=lambda r: r["elements"])
        if len(cuts) >= 2:
            _cut_chart(ctx, cuts)
        lines += ["", _cut_section(cuts, summary.get("tolerance"), len(cuts) >= 2)]
    return "\n".join(lines)


def _size_table(rows):
    """One size series as Markdown table lines, with the peaks that read the process's floor (_floored)
    written as at most that floor and their ratio left out, and a line saying so."""
    floored = _floored(rows)
    lines = ["| elements | n | dense | hierarchical | time h / d | dense peak | hierarchical peak | memory h / d | stored / dense | "
             "largest rank | displacement diff. | traction diff. |",
             "|---|---|---|---|---|---|---|---|---|---|---|---|"]

    def peak(i, r, key):
        return f"≤ {r[key]:,.0f} MB (floor)" if (i, key) in floored else f"{r[key]:,.0f} MB"

    for i, r in enumerate(rows):
        ratio = "–" if (i, "hierarchical_peak_mb") in floored else f"{r['memory_ratio']:.2f}"
        lines.append(f"| {r['elements']:,} | {r['equations']:,} | {rl.seconds_text(r['dense_s'])} | "
                     f"{rl.seconds_text(r['hierarchical_s'])} | {r['time_ratio']:.2f} | {peak(i, r, 'dense_peak_mb')} | "
                     f"{peak(i, r, 'hierarchical_peak_mb')} | {ratio} | {r['compression_ratio']:.3f} | "
                     f"{r['largest_rank']} | {r['displacement_difference']:.1e} | {r['traction_difference']:.1e} |")
    if floored:
        lines += ["", "*(floor)*: the peak of that solve was below the resident memory the process still held from the "
                  "larger solves before it (the high-water mark can be reset only to what is resident), so the cell gives "
                  "that floor, not the solve's peak, and the chart leaves it out. The stored fraction is the memory measure "
                  "to read there."]
    return lines


def _cut_chart(ctx, cuts):
    """A cut step's and the precompute's time against n, both backends (log-log)."""
    fig, (ax_s, ax_p) = _two_axes()
    ns = [3 * r["elements"] for r in cuts]
    for ax, key, ylabel in ((ax_s, "step_s", "exact cut step, median (s)"), (ax_p, "precompute_s", "table kept for cuts (s)")):
        for backend, label, marker in (("dense", "dense LU", "s"), ("hierarchical", "hierarchical (H-LU)", "o")):
            ts = [r[f"{backend}_{key}"] for r in cuts]
            ax.plot(ns, ts, marker=marker, color="black" if backend == "dense" else None,
                    label=f"{label}: n^{_exp(rl.fit_exponent(ns, ts))}")
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel("equations n before the cut (3 per element)")
        ax.set_ylabel(ylabel)
        ax.legend(fontsize=7, title="fitted exponent p of y ≈ c·n^p", title_fontsize=7)
    ax_s.set_title("a cut step on either backend")
    ax_p.set_title("the precompute it starts from")
    rl.save(fig, ctx.image("hmatrix_cuts"))


def _cut_section(cuts, tolerance, chart):
    """The cut study: the same exact cut steps on a table kept for cuts on either backend."""
    if not cuts:
        return ""
    lines = ["**Cuts on either backend** (docs/cutting.md, \"On either backend\"): at each size a table kept for cuts (its "
             "region the top face within 0.3 edges of its centre) on each backend, then the same exact cut steps across the "
             f"top, each step's wall time (median over the steps); ACA+ at {tolerance}. The update is the same code on both: "
             "bordering plus Woodbury on the kept factorisation (dense LU or H-LU), so the final tables differ by the "
             "compression only.", ""] + (["![cut steps against n](images/hmatrix_cuts.png)", ""] if chart else []) + [
             "| elements | region | steps | step, dense | step, hierarchical | step h / d | precompute, dense | precompute, hierarchical | "
             "factors, dense | factors, hierarchical | columns diff. | base state diff. |",
             "|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in cuts:
        lines.append(f"| {r['elements']:,} | {r['region_elements']} | {r['steps']} | {rl.seconds_text(r['dense_step_s'])} | "
                     f"{rl.seconds_text(r['hierarchical_step_s'])} | {r['step_ratio']:.2f} | {rl.seconds_text(r['dense_precompute_s'])} | "
                     f"{rl.seconds_text(r['hierarchical_precompute_s'])} | {r['dense_factor_mb']:,.0f} MB | "
                     f"{r['hierarchical_factor_mb']:,.0f} MB | {r['columns_difference']:.1e} | {r['base_difference']:.1e} |")
    big = cuts[-1]
    verdict = "faster" if big["step_ratio"] < 1.0 else "slower"
    lines += ["", f"At {big['elements']:,} elements a cut step on the H-LU is {verdict} than on the dense LU "
              f"({big['step_ratio']:.2f}× its time) and its factors take {big['hierarchical_factor_mb'] / big['dense_factor_mb']:.2f}× "
              "the dense factors' memory."]
    return "\n".join(lines)
