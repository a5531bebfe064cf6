"""Cut-step latency of the exact update (system and table) against n, with the goals (20 ms at
n = 1,584, 0.25 s at n = 9,000), the step's flop floor and the refactorisation it replaces
(benchmarks/bench_cut.cpp, part 2; docs/cutting.md, "Timing").

Data: DIR/cut_latency/latency.csv (bench_cut --csv-dir: equations, nx, ny, nz, region_elements,
steps, then changed_elements_per_step, changed_columns, exact_seconds, integration_seconds,
system_seconds, table_seconds, refactor_seconds, precompute_seconds, agreement, final_rank,
dgemm_gflops, flop_floor_seconds) and DIR/cut_latency/run.csv.
"""

import math

from matplotlib.ticker import FuncFormatter

import report_lib as rl

NAME = "cut_latency"
TITLE = "Cut-step latency against n"
ORDER = 40

GOALS = [(1584, 0.020, "20 ms at n = 1,584"), (9000, 0.25, "0.25 s at n = 9,000")]  # docs/cutting.md, "Timing"
QUICK_EQUATIONS = "1344,1800,2400"  # 1,344: the smallest box with room for the cut (bench_cut's block_near)
FULL_EQUATIONS = "1584,3000,4752,9000,12000,15000"


def run(ctx):
    d = ctx.part_dir(NAME)
    args = [ctx.program("bench_cut"), "--no-table1", "--no-gap", "--csv-dir", d, "--json", d / "bench_cut.json"]
    args += ["--quick", "--equations", QUICK_EQUATIONS] if ctx.quick else ["--equations", FULL_EQUATIONS]
    stdout, _ = ctx.run(args, NAME, timeout=1200)
    (d / "bench_cut.txt").write_text(stdout)


def _at(rows, n_goal, key):
    """(value, n) at n_goal: the measured size within 5 % of it, else log-log interpolation between
    the sizes around it (n is then n_goal); None outside the measured range."""
    near = min(rows, key=lambda r: abs(r["equations"] - n_goal))
    if abs(near["equations"] - n_goal) <= 0.05 * n_goal:
        return near[key], near["equations"], False
    below = [r for r in rows if r["equations"] < n_goal]
    above = [r for r in rows if r["equations"] > n_goal]
    if not below or not above:
        return None, None, False
    a, b = max(below, key=lambda r: r["equations"]), min(above, key=lambda r: r["equations"])
    w = math.log(n_goal / a["equations"]) / math.log(b["equations"] / a["equations"])
    return math.exp((1 - w) * math.log(a[key]) + w * math.log(b[key])), n_goal, True


def _chart(ctx, rows, fits):
    fig, ax = rl.new_figure(6.8, 4.6)
    ns = [r["equations"] for r in rows]
    series = [("exact_seconds", "exact update (system + table)", "tab:red", "o", "-"),
              ("flop_floor_seconds", "flop floor: 2 n² d at the measured dgemm rate", "black", "v", ":"),
              ("refactor_seconds", "refactorisation (assembly, LU, table)", "tab:gray", "s", "--")]
    for key, label, colour, marker, style in series:
        p = fits.get(key)
        ax.plot(ns, [r[key] for r in rows], marker=marker, ls=style, color=colour,
                label=label + (f" (∝ n^{p:.2f})" if p is not None else ""))
    for (n_goal, seconds, label), colour in zip(GOALS, ["tab:green", "tab:purple"]):
        ax.axhline(seconds, color=colour, lw=1.2, alpha=0.8, label=f"goal {label} (★: that n)")
        ax.plot([n_goal], [seconds], marker="*", ms=11, color=colour, ls="none")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.xaxis.set_major_formatter(FuncFormatter(lambda v, _: f"{v:,.0f}"))
    ax.xaxis.set_minor_formatter(FuncFormatter(lambda v, _: f"{v:,.0f}" if str(int(round(v)))[0] in "1235" else ""))
    ax.tick_params(axis="x", which="both", labelsize=7)
    ax.set_xlabel("equations n")
    ax.set_ylabel("seconds per cut step")
    ax.set_title("Exact cut-step latency against n (median over 6 steps of one cut)", fontsize=9)
    ax.legend(fontsize=7)
    rl.save(fig, ctx.image("cut_latency"))


def _table(rows):
    lines = ["| n | d | exact | integration | system | table | floor | exact / floor | dgemm GFLOP/s | refactorisation | "
             "exact / refactorisation | agreement | rank |", "|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        lines.append(f"| {r['equations']:,} | {r['changed_columns']} | {rl.seconds_text(r['exact_seconds'])} | "
                     f"{rl.seconds_text(r['integration_seconds'])} | {rl.seconds_text(r['system_seconds'])} | "
                     f"{rl.seconds_text(r['table_seconds'])} | {rl.seconds_text(r['flop_floor_seconds'])} | "
                     f"{r['exact_seconds'] / r['flop_floor_seconds']:.2g} | {r['dgemm_gflops']:.3g} | "
                     f"{rl.seconds_text(r['refactor_seconds'])} | {r['exact_seconds'] / r['refactor_seconds']:.2g} | "
                     f"{r['agreement']:.1e} | {r['final_rank']} |")
    return "\n".join(lines)


def _goal_text(rows):
    text = []
    for n_goal, seconds, label in GOALS:
        value, n, interpolated = _at(rows, n_goal, "exact_seconds")
        if value is None:
            text.append(f"The goal {label} is outside the sizes measured ({rows[0]['equations']:,}–{rows[-1]['equations']:,}).")
            continue
        floor, _, _ = _at(rows, n_goal, "flop_floor_seconds")
        where = f"at n = {n:,}" + (" (interpolated log-log between the sizes around it)" if interpolated else "")
        verdict = "met" if value <= seconds else "**missed**"
        text.append(f"Goal {label}: {verdict}, {rl.seconds_text(value)} {where}, {value / seconds:.2g}x the goal; "
                    f"the flop floor there is {rl.seconds_text(floor)} ({floor / seconds:.2g}x the goal).")
    for _, seconds, label in GOALS:
        ok = [r["equations"] for r in rows if r["exact_seconds"] <= seconds]
        text.append(f"Largest n measured within {rl.seconds_text(seconds)}: " + (f"{max(ok):,}." if ok else "none."))
    return text


def _load_text(run):
    """A warning when other work shared the cores: every wall-clock figure is then slower."""
    load, threads = run.get("load_average_at_start"), run.get("threads")
    if isinstance(load, (int, float)) and isinstance(threads, int) and load > threads:
        return (f"**The machine was shared during this run** (load average {load:.2f} at the start for {threads} threads): "
                "the seconds are slower than on an idle machine; the ratios within the run hold better.")
    return ""


def render(ctx):
    d = ctx.part_dir(NAME)
    rows = sorted(rl.read_csv(d / "latency.csv"), key=lambda r: r["equations"])
    run = (rl.read_csv(d / "run.csv") or [{}])[0]
    ns = [r["equations"] for r in rows]
    fits = {k: rl.fit_exponent(ns, [r[k] for r in rows]) for k in ("exact_seconds", "flop_floor_seconds", "refactor_seconds")}
    _chart(ctx, rows, fits)
    above = [r["exact_seconds"] / r["flop_floor_seconds"] for r in rows]
    vs_ref = [r["exact_seconds"] / r["refactor_seconds"] for r in rows]
    load = run.get("load_average_at_start")
    intro = ("The exact update of system and table after each of the 6 steps of one cut (opening and five extensions) of a "
             "box on its base, region: the 1,000 free elements nearest the cut (benchmarks/bench_cut.cpp, docs/cutting.md). "
             "Latency: the median step, integration of the changed elements included. *d*: changed columns per step, "
             "3 × (modified + added elements), the rows and columns of A* the step changes. *Flop floor*: 2 n² d flops, "
             "the least an exact step does (the inverse applied to the d changed columns), at the rate of a bare dgemm "
             "(n × n times n × d) measured in the same run. *Refactorisation*: re-assembly, LU and table after the last "
             "step. Times: the step figures are medians over the 6 steps of one cut (not repeated runs: each step changes the "
             "body, and issue 39 profiles them), the refactorisation and the precompute one run each, the dgemm rate a "
             f"median of 5. {run.get('threads', '?')} threads, {run.get('dense_backend', '?')}"
             + (f", load average {load:.2f} at the start." if isinstance(load, (int, float)) and load >= 0 else "."))
    fit_text = ", ".join(f"{name} ∝ n^{fits[k]:.2f}" for k, name in
                         (("exact_seconds", "exact"), ("flop_floor_seconds", "floor"), ("refactor_seconds", "refactorisation"))
                         if fits[k] is not None)
    text = [f"Fitted exponents (least squares, log-log, n = {ns[0]:,}–{ns[-1]:,}): {fit_text}." if fit_text else
            "One size only: no exponent fitted.",
            f"Latency / flop floor: {min(above):.2g}–{max(above):.2g} (" +
            ", ".join(f"{a:.2g} at n = {n:,}" for a, n in zip(above, ns)) + ").",
            f"Exact / refactorisation: {min(vs_ref):.2g}–{max(vs_ref):.2g}."]
    text += _goal_text(rows)
    text.append(_load_text(run))
    worst = max(r["agreement"] for r in rows)
    text.append(f"Agreement of the updated table with the refactorisation: ≤ {worst:.1e} (max relative difference).")
    return "\n\n".join([intro, "![Exact cut-step latency against n](images/cut_latency.png)", _table(rows), " ".join(t for t in text if t)])
