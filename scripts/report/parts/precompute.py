"""Precompute time against n (issue 24, item 4): GreensTable::compute split into assembly,
factorisation and table, beside the bare LAPACK dgetrf (+ dgetrs of the same right-hand sides) at
the same n in the same process (bench_contact --no-updates; docs/benchmarks.md "bench_contact").

CSV precompute.csv, one row per box size: N (cells per edge), equations, elements, then seconds
assembly_s, factorization_s, table_s, precompute_s (their sum), bare_factorization_s (dgetrf),
bare_solve_s (dgetrs), bare_s (their sum), eigen_lu_s (Eigen PartialPivLU of the same n), and the ratios precompute_over_bare,
assembly_over_bare_factorization, factorization_over_bare.
"""

import json

import report_lib as rl

NAME = "precompute"
TITLE = "Precompute against n"
ORDER = 50

FULL_SIZES = [5, 7, 9, 12, 15, 18, 21]  # n = 780 … 15372 (about 2 minutes on 2 idle cores)
QUICK_SIZES = [4, 6, 8, 10]  # n = 480, 1152, 2112, 3360 (seconds)
# docs/benchmarks.md ("bench_assembly", "bench_contact"): the targets, judged at the largest n.
ASSEMBLY_TARGET = 0.5  # assembly / bare dgetrf
PRECOMPUTE_TARGET = 1.5  # (assembly + factorisation + table) / (bare dgetrf + dgetrs)
TARGET_N = 6720  # the size the targets are stated at (issue 9)

COLUMNS = ["N", "equations", "elements", "assembly_s", "factorization_s", "table_s", "precompute_s", "bare_factorization_s",
           "bare_solve_s", "bare_s", "eigen_lu_s", "precompute_over_bare", "assembly_over_bare_factorization", "factorization_over_bare"]


def run(ctx):
    d = ctx.part_dir(NAME)
    sizes = QUICK_SIZES if ctx.quick else FULL_SIZES
    raw = d / "bench_contact.json"
    ctx.run([ctx.program("bench_contact"), "--no-updates", "--sizes", ",".join(map(str, sizes)), "--json", raw], NAME,
            timeout=900)
    rows = []
    for N, s in zip(sizes, json.loads(raw.read_text())["sizes"]):
        pre = s["assembly_seconds"] + s["factorization_seconds"] + s["table_seconds"]
        bare = s["bare_factorization_seconds"] + s["bare_solve_seconds"]
        rows.append({"N": N, "equations": s["equations"], "elements": s["elements"], "assembly_s": s["assembly_seconds"],
                     "factorization_s": s["factorization_seconds"], "table_s": s["table_seconds"], "precompute_s": pre,
                     "bare_factorization_s": s["bare_factorization_seconds"], "bare_solve_s": s["bare_solve_seconds"],
                     "bare_s": bare, "eigen_lu_s": s.get("eigen_lu_seconds"), "precompute_over_bare": s["precompute_over_bare"],
                     "assembly_over_bare_factorization": s["assembly_over_bare_factorization"],
                     "factorization_over_bare": s["factorization_over_bare"]})
    rl.write_csv(d / "precompute.csv", rows, COLUMNS)


SERIES = [("assembly_s", "assembly", "-", "o"), ("factorization_s", "factorisation (dgetrf on A*)", "-", "s"),
          ("table_s", "table (dgetrs)", "-", "^"), ("precompute_s", "whole precompute", "-", "D"),
          ("bare_factorization_s", "bare dgetrf (baseline)", "--", "v"), ("bare_s", "bare dgetrf + dgetrs", ":", "x"),
          ("eigen_lu_s", "Eigen PartialPivLU (peer)", "-.", "P")]


def _exp_text(p):
    return "–" if p is None else f"{p:.2f}"


def render(ctx):
    rows = rl.read_csv(ctx.part_dir(NAME) / "precompute.csv")
    rows.sort(key=lambda r: r["equations"])
    ns = [r["equations"] for r in rows]
    exps = {}
    fig, ax = rl.new_figure(6.8, 4.6)
    for key, label, style, marker in SERIES:
        if any(r.get(key) is None for r in rows):
            continue  # a column an older bench_contact did not write
        ts = [r[key] for r in rows]
        exps[key] = rl.fit_exponent(ns, ts)
        color = "black" if key.startswith("bare") else ("grey" if key.startswith("eigen") else None)
        ax.plot(ns, ts, linestyle=style, marker=marker, color=color, label=f"{label}: n^{_exp_text(exps[key])}")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("equations n (3 per element)")
    ax.set_ylabel("time (s)")
    ax.set_title("GreensTable::compute against n, beside the bare LAPACK LU")
    ax.legend(fontsize=7, title="fitted exponent p of t ≈ c·n^p", title_fontsize=7)
    rl.save(fig, ctx.image("precompute_vs_n"))

    lines = [
        "The one-time precompute of the haptic path (`GreensTable::compute`, docs/contact.md) split into assembly "
        "(H, G, gravity, A* and right-hand sides), factorisation (`dgetrf` on A*) and table (`dgetrs`, 3|region| + 1 "
        "right-hand sides), on bench_contact's boxes of N × N × (N − 1) cells, beside the bare `dgetrf` and `dgetrs` of "
        "the same n and right-hand sides measured in the same process (`bench_contact --no-updates`). The legend gives "
        "each series' exponent fitted by least squares over all sizes (expected ≈ 2 for the assembly, O(E²) element "
        "pairs, and ≈ 3 for the LU; at small n the LU's exponent is below 3 because BLAS runs below its peak there). "
        "Times: one run of each size (bench_contact does not repeat them; the bare baselines ran in the same process, "
        "so the ratios compare like with like).",
        "", "![precompute time against n](images/precompute_vs_n.png)", "",
        "| n | elements | assembly | factorisation | table | precompute | bare dgetrf | bare dgetrs | "
        "precompute / bare | assembly / bare dgetrf | factorisation + table / bare |",
        "|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        lines.append(f"| {r['equations']} | {r['elements']} | {rl.seconds_text(r['assembly_s'])} | "
                     f"{rl.seconds_text(r['factorization_s'])} | {rl.seconds_text(r['table_s'])} | "
                     f"{rl.seconds_text(r['precompute_s'])} | {rl.seconds_text(r['bare_factorization_s'])} | "
                     f"{rl.seconds_text(r['bare_solve_s'])} | {r['precompute_over_bare']:.2f} | "
                     f"{r['assembly_over_bare_factorization']:.2f} | {r['factorization_over_bare']:.2f} |")
    lines.append("")
    lines.append(f"Fitted exponents over all sizes: assembly {_exp_text(exps['assembly_s'])} (expected ≈ 2), factorisation "
                 f"{_exp_text(exps['factorization_s'])} and bare dgetrf {_exp_text(exps['bare_factorization_s'])} "
                 f"(expected ≈ 3), whole precompute {_exp_text(exps['precompute_s'])}.")
    if len(rows) >= 4:  # the large-n end alone, where fixed costs and BLAS's ramp-up matter less
        big = rows[-3:]
        fit = {k: _exp_text(rl.fit_exponent([r["equations"] for r in big], [r[k] for r in big]))
               for k in ("assembly_s", "factorization_s", "bare_factorization_s", "precompute_s")}
        lines[-1] += (f" Over the three largest (n = {big[0]['equations']}–{big[-1]['equations']}): assembly "
                      f"{fit['assembly_s']}, factorisation {fit['factorization_s']}, bare dgetrf "
                      f"{fit['bare_factorization_s']}, whole precompute {fit['precompute_s']}.")
    if rows and rows[-1].get("eigen_lu_s"):
        ratios = [r["eigen_lu_s"] / r["bare_factorization_s"] for r in rows if r.get("eigen_lu_s") and r["bare_factorization_s"]]
        lines += ["", f"Eigen's dense LU (`PartialPivLU`, which this build hands to LAPACKE's `dgetrf`) on a matrix of the same n: "
                  f"{min(ratios):.2f}–{max(ratios):.2f}× the bare `dgetrf` ({ratios[-1]:.2f}× at n = {rows[-1]['equations']}); "
                  f"bemsurg's factorisation of A* is {rows[-1]['factorization_s'] / rows[-1]['eigen_lu_s']:.2f}× Eigen's LU there."]
    if rows:
        lines += ["", _verdict(rows)]
    return "\n".join(lines)


def _verdict(rows):
    """The targets of docs/benchmarks.md, judged at the largest n measured (the small sizes are
    dominated by fixed costs and timer noise), and where they are missed at smaller n."""
    big = rows[-1]
    out = []
    a, p = big["assembly_over_bare_factorization"], big["precompute_over_bare"]
    if a <= ASSEMBLY_TARGET:
        out.append(f"At n = {big['equations']} the assembly takes {a:.2f}× the bare `dgetrf` (target ≤ {ASSEMBLY_TARGET}): met.")
    else:
        out.append(f"**Target missed**: at n = {big['equations']} the assembly takes {a:.2f}× the bare `dgetrf` "
                   f"(target ≤ {ASSEMBLY_TARGET}).")
    if p <= PRECOMPUTE_TARGET:
        out.append(f"The whole precompute takes {p:.2f}× the bare `dgetrf` + `dgetrs` (target ≤ {PRECOMPUTE_TARGET}): met.")
    else:
        out.append(f"**Target missed**: the whole precompute takes {p:.2f}× the bare `dgetrf` + `dgetrs` "
                   f"(target ≤ {PRECOMPUTE_TARGET}).")
    small = [r for r in rows[:-1] if r["precompute_over_bare"] > PRECOMPUTE_TARGET
             or r["assembly_over_bare_factorization"] > ASSEMBLY_TARGET]
    if small:
        out.append("At smaller n the targets are missed at " + ", ".join(
            f"n = {r['equations']} (assembly {r['assembly_over_bare_factorization']:.2f}×, precompute "
            f"{r['precompute_over_bare']:.2f}×)" for r in small)
            + ": there the O(n²) assembly is not yet small beside the O(n³) LU.")
    if big["equations"] < TARGET_N:
        out.append(f"(The targets are stated for n ≈ {TARGET_N}; this run's largest n is {big['equations']}.)")
    return " ".join(out)
