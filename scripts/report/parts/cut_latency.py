"""Cut-step latency of the exact update (system and table) against n, with the goals (20 ms at
n = 1,584, 0.25 s at n = 9,000), the step's arithmetic floor, where the step's time goes and the
refactorisation it replaces (benchmarks/bench_cut.cpp, part 2; docs/cutting.md, "Timing").

Data: DIR/cut_latency/latency.csv (bench_cut --csv-dir: equations, nx, ny, nz, region_elements,
steps, then changed_elements_per_step, changed_columns, exact_seconds, integration_seconds,
system_seconds, table_seconds, refactor_seconds, precompute_seconds, agreement, final_rank,
dgemm_gflops, the profile change_seconds, solve_seconds, solve_columns, correction_seconds,
snapshot_seconds, gemm_seconds, finish_seconds, table_gemm_flops, snapshot_bytes, solve_base_size,
dgetrs_gflops, and solve_floor_seconds, gemm_floor_seconds, arithmetic_floor_seconds; from issue 39
also first_response_seconds, one_step_seconds, reach_elements, first_response_solve_columns and the
same for a probe beside the cut, first_response_beside_seconds and _solve_columns, beside_metres) and
DIR/cut_latency/run.csv. Data of a run before the profile (flop_floor_seconds: 2 n^2 d at the dgemm
rate) still render, without the profile.
"""

import math

from matplotlib.ticker import FuncFormatter

import report_lib as rl

NAME = "cut_latency"
TITLE = "Cut-step latency against n"
ORDER = 40

GOALS = [(1584, 0.020, "20 ms at n = 1,584"), (9000, 0.25, "0.25 s at n = 9,000")]  # docs/cutting.md, "Timing"
# Issue 39's goals for the first response (the loop's exact rows within reach), checked against first_response_seconds.
FIRST_GOALS = [(1620, 0.020, "first response 20 ms at n = 1,620"), (4704, 0.050, "first response 50 ms at n = 4,704"),
               (8976, 0.100, "first response 0.1 s at n = 8,976")]
QUICK_EQUATIONS = "1344,1800,2400"  # 1,344: the smallest box with room for the cut (bench_cut's block_near)
FULL_EQUATIONS = "1584,3000,4752,9000,12000,15000"
# Where a step's time goes (GreensTableUpdateResult's profile), in the order the step takes them.
PHASES = [("integration_seconds", "integration (changed rows and columns)", "tab:olive"),
          ("change_seconds", "the step's terms X, U, V and right-hand sides", "tab:cyan"),
          ("solve_seconds", "LU solves (dgetrs)", "tab:blue"),
          ("correction_seconds", "accumulated rank (V, W, capacitance, Woodbury)", "tab:orange"),
          ("snapshot_seconds", "new snapshot: allocation and copy (first touches)", "tab:pink"),
          ("gemm_seconds", "table GEMMs (X T, Woodbury term)", "tab:red"),
          ("finish_seconds", "fresh columns, checks, slots", "tab:gray")]


def _floor_key(rows):
    """The floor the data carry: the arithmetic floor, or the old flop floor (2 n^2 d)."""
    return "arithmetic_floor_seconds" if all("arithmetic_floor_seconds" in r for r in rows) else "flop_floor_seconds"


def _profiled(rows):
    return all(all(k in r and isinstance(r[k], (int, float)) for k, _, _ in PHASES) for r in rows)


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
    fig, ax = rl.new_figure(6.8, 6.4)
    ns = [r["equations"] for r in rows]
    floor = _floor_key(rows)
    floor_label = ("arithmetic floor (LU solves at the dgetrs rate + table GEMMs at the dgemm rate)"
                   if floor == "arithmetic_floor_seconds" else "flop floor: 2 n² d at the measured dgemm rate")
    two_phase = all("first_response_seconds" in r for r in rows)
    series = [("exact_seconds", "exact update to the complete table" + (" (two phases)" if two_phase else " (system + table)"),
               "tab:red", "o", "-")]
    if two_phase:
        series += [("first_response_seconds", "first response (rows within 2 cm of the probe, over the explicit inverse)",
                    "tab:blue", "D", "-")]
        if all("first_response_lu_seconds" in r for r in rows):
            series += [("first_response_lu_seconds", "first response over the LU (columns within reach)", "tab:brown", "P", "-.")]
        if all("first_response_floor_seconds" in r for r in rows):
            series += [("first_response_floor_seconds", "first response's floor (V_sᵀ A0⁻¹ at the dgemm rate)", "tab:blue", "1", ":")]
        if all("first_response_beside_seconds" in r for r in rows):
            series += [("first_response_beside_seconds", "first response, probe 5 cm beside the cut", "tab:cyan", "d", "-.")]
        series += [("one_step_seconds", "the same step in one call (before the split)", "tab:orange", "x", "--")]
    series += [(floor, floor_label, "black", "v", ":"),
               ("refactor_seconds", "refactorisation (assembly, LU, table)", "tab:gray", "s", "--")]
    for key, label, colour, marker, style in series:
        p = fits.get(key, rl.fit_exponent(ns, [r[key] for r in rows]))
        ax.plot(ns, [r[key] for r in rows], marker=marker, ls=style, color=colour,
                label=label + (f" (∝ n^{p:.2f})" if p is not None else ""))
    for (n_goal, seconds, label), colour in zip(GOALS, ["tab:green", "tab:purple"]):
        ax.axhline(seconds, color=colour, lw=1.2, alpha=0.8, label=f"goal {label} (★: that n)")
        ax.plot([n_goal], [seconds], marker="*", ms=11, color=colour, ls="none")
    if two_phase:
        ax.plot([g[0] for g in FIRST_GOALS], [g[1] for g in FIRST_GOALS], marker="*", ms=11, color="tab:blue", mfc="none",
                ls="none", label="first response goals (issue 39): 20 ms, 50 ms, 0.1 s at n = 1,620, 4,704, 8,976")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.xaxis.set_major_formatter(FuncFormatter(lambda v, _: f"{v:,.0f}"))
    ax.xaxis.set_minor_formatter(FuncFormatter(lambda v, _: f"{v:,.0f}" if str(int(round(v)))[0] in "1235" else ""))
    ax.tick_params(axis="x", which="both", labelsize=7)
    ax.set_xlabel("equations n")
    ax.set_ylabel("seconds per cut step")
    ax.set_title("Exact cut-step latency against n (median over 6 steps of one cut)", fontsize=9)
    ax.legend(fontsize=6.5, loc="upper center", bbox_to_anchor=(0.5, -0.12), ncol=1)  # below: the series fill the axes
    rl.save(fig, ctx.image("cut_latency"))


def _profile_chart(ctx, rows):
    """Stacked bars: each phase's share of the median step, one bar per n, the floor marked."""
    fig, ax = rl.new_figure(6.8, 4.2)
    xs = range(len(rows))
    bottom = [0.0] * len(rows)
    for key, label, colour in PHASES:
        values = [r[key] for r in rows]
        ax.bar(xs, values, bottom=bottom, color=colour, label=label, width=0.6)
        bottom = [b + v for b, v in zip(bottom, values)]
    ax.plot(xs, [r["arithmetic_floor_seconds"] for r in rows], "kv", ls="none", label="arithmetic floor")
    ax.plot(xs, [r["exact_seconds"] for r in rows], "o", color="tab:red", mfc="none", ls="none", label="exact step (median)")
    ax.set_xticks(list(xs))
    ax.set_xticklabels([f"{r['equations']:,}" for r in rows], fontsize=7)
    ax.set_xlabel("equations n")
    ax.set_ylabel("seconds per cut step (medians of each phase)")
    ax.set_title("Where the exact step's time goes", fontsize=9)
    ax.legend(fontsize=6.5, loc="upper left")
    rl.save(fig, ctx.image("cut_latency_profile"))


def _profile_table(rows):
    lines = ["| n | integration | terms | LU solves (right-hand sides) | accumulated rank | snapshot (MB) | table GEMMs | "
             "finish | sum of phases | floor: solves + GEMMs | dgetrs GFLOP/s |", "|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        total = sum(r[k] for k, _, _ in PHASES)
        lines.append(f"| {r['equations']:,} | {rl.seconds_text(r['integration_seconds'])} | {rl.seconds_text(r['change_seconds'])} | "
                     f"{rl.seconds_text(r['solve_seconds'])} ({r['solve_columns']:.0f}) | {rl.seconds_text(r['correction_seconds'])} | "
                     f"{rl.seconds_text(r['snapshot_seconds'])} ({r['snapshot_bytes'] / 1e6:.0f}) | {rl.seconds_text(r['gemm_seconds'])} | "
                     f"{rl.seconds_text(r['finish_seconds'])} | {rl.seconds_text(total)} | "
                     f"{rl.seconds_text(r['solve_floor_seconds'])} + {rl.seconds_text(r['gemm_floor_seconds'])} | "
                     f"{r['dgetrs_gflops']:.3g} |")
    return "\n".join(lines)


def _profile_text(rows):
    """The largest phase at each size, and the share of the four phases the first response cannot skip."""
    out = []
    for r in rows:
        total = sum(r[k] for k, _, _ in PHASES)
        if total <= 0:
            continue
        top = max(PHASES, key=lambda ph: r[ph[0]])
        must = sum(r[k] for k in ("integration_seconds", "change_seconds", "solve_seconds", "correction_seconds"))
        out.append(f"n = {r['equations']:,}: {top[1]} is the largest phase ({r[top[0]] / total:.0%}); "
                   f"integration, the step's terms, the LU solves and the accumulated rank take {must / total:.0%}, "
                   f"the table's GEMMs, the new snapshot and its finish {1 - must / total:.0%}")
    return ("Profile (medians of each phase over the steps): " + "; ".join(out) + ". Every table column depends on the "
            "step's solves (Z = A'⁻¹ U_s, docs/cutting.md), so a first response that makes only the columns within the "
            "tools' reach exact still pays for the first four.") if out else ""


def _table(rows):
    floor = _floor_key(rows)
    lines = ["| n | d | exact | integration | system | table | floor | exact / floor | dgemm GFLOP/s | refactorisation | "
             "exact / refactorisation | agreement | rank |", "|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    if all("first_response_seconds" in r for r in rows):
        lines = ["| n | d | first response (elements in reach) | first / one call | exact (two phases) | one call | integration | "
                 "system | table | floor | exact / floor | dgemm GFLOP/s | refactorisation | exact / refactorisation | agreement | rank |",
                 "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        first = (f"{rl.seconds_text(r['first_response_seconds'])} ({r['reach_elements']:.0f}) | "
                 f"{r['first_response_seconds'] / r['one_step_seconds']:.2g} | " if "first_response_seconds" in r else "")
        one = f"{rl.seconds_text(r['one_step_seconds'])} | " if "one_step_seconds" in r else ""
        lines.append(f"| {r['equations']:,} | {r['changed_columns']} | {first}{rl.seconds_text(r['exact_seconds'])} | {one}"
                     f"{rl.seconds_text(r['integration_seconds'])} | {rl.seconds_text(r['system_seconds'])} | "
                     f"{rl.seconds_text(r['table_seconds'])} | {rl.seconds_text(r[floor])} | "
                     f"{r['exact_seconds'] / r[floor]:.2g} | {r['dgemm_gflops']:.3g} | "
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
        floor, _, _ = _at(rows, n_goal, _floor_key(rows))
        where = f"at n = {n:,}" + (" (interpolated log-log between the sizes around it)" if interpolated else "")
        verdict = "met" if value <= seconds else "**missed**"
        text.append(f"Goal {label}: {verdict}, {rl.seconds_text(value)} {where}, {value / seconds:.2g}x the goal; "
                    f"the floor there is {rl.seconds_text(floor)} ({floor / seconds:.2g}x the goal).")
    if all("first_response_seconds" in r for r in rows):
        for n_goal, seconds, label in FIRST_GOALS:
            value, n, interpolated = _at(rows, n_goal, "first_response_seconds")
            if value is None:
                continue
            where = f"at n = {n:,}" + (" (interpolated log-log)" if interpolated else "")
            floor = ""
            if all("first_response_floor_seconds" in r for r in rows):
                f, _, _ = _at(rows, n_goal, "first_response_floor_seconds")
                floor = f"; its GEMM's floor there is {rl.seconds_text(f)} ({f / seconds:.2g}x the goal)"
            text.append(f"Goal {label}: {'met' if value <= seconds else '**missed**'}, {rl.seconds_text(value)} {where}, "
                        f"{value / seconds:.2g}x the goal{floor}.")
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
    floor = _floor_key(rows)
    fits = {k: rl.fit_exponent(ns, [r[k] for r in rows]) for k in ("exact_seconds", floor, "refactor_seconds")}
    _chart(ctx, rows, fits)
    profiled = _profiled(rows) and floor == "arithmetic_floor_seconds"
    if profiled:
        _profile_chart(ctx, rows)
    above = [r["exact_seconds"] / r[floor] for r in rows]
    vs_ref = [r["exact_seconds"] / r["refactor_seconds"] for r in rows]
    load = run.get("load_average_at_start")
    intro = ("The exact update of system and table after each of the 6 steps of one cut (opening and five extensions) of a "
             "box on its base, region: the 1,000 free elements nearest the cut (benchmarks/bench_cut.cpp, docs/cutting.md). "
             "Latency: the median step, integration of the changed elements included. *d*: changed columns per step, "
             "3 × (modified + added elements), the rows and columns of A* the step changes. "
             + ("*Arithmetic floor*: the LU solves the step needs (the changed columns of the Woodbury term, the unit "
                "columns of the reshaped elements, the fresh table columns and the base state; the new dofs' unit columns "
                "need none), 2 n² flops each at the rate dgetrs reaches on the table's own factors with as many right-hand "
                "sides, plus the table's two GEMMs at the rate of a bare dgemm (n × n times n × d), both measured in the same "
                "run. "
                if floor == "arithmetic_floor_seconds" else
                "*Flop floor*: 2 n² d flops at the rate of a bare dgemm (n × n times n × d) measured in the same run. ")
             + "*Refactorisation*: re-assembly, LU and table after the last "
             "step. Times: the step figures are medians over the 6 steps of one cut (not repeated runs: each step changes the "
             "body, and issue 39 profiles them), the refactorisation and the precompute one run each, the dgemm rate a "
             f"median of 5. {run.get('threads', '?')} threads, {run.get('dense_backend', '?')}"
             + (f", load average {load:.2f} at the start." if isinstance(load, (int, float)) and load >= 0 else "."))
    fit_text = ", ".join(f"{name} ∝ n^{fits[k]:.2f}" for k, name in
                         (("exact_seconds", "exact"), (floor, "floor"), ("refactor_seconds", "refactorisation"))
                         if fits[k] is not None)
    text = [f"Fitted exponents (least squares, log-log, n = {ns[0]:,}–{ns[-1]:,}): {fit_text}." if fit_text else
            "One size only: no exponent fitted.",
            f"Latency / floor: {min(above):.2g}–{max(above):.2g} (" +
            ", ".join(f"{a:.2g} at n = {n:,}" for a, n in zip(above, ns)) + ").",
            f"Exact / refactorisation: {min(vs_ref):.2g}–{max(vs_ref):.2g}."]
    if all("first_response_seconds" in r for r in rows):
        firsts = [r["first_response_seconds"] / r["one_step_seconds"] for r in rows]
        completes = [r["exact_seconds"] / r["one_step_seconds"] for r in rows]
        worst_first = max(r["first_response_agreement"] for r in rows)
        text.append(f"First response / the step in one call (same run, same steps): {min(firsts):.2g}–{max(firsts):.2g} (" +
                    ", ".join(f"{a:.2g} at n = {n:,}" for a, n in zip(firsts, ns)) + f"); the complete table in two phases / one "
                    f"call: {min(completes):.2g}–{max(completes):.2g}. The first response's columns and the complete table agree with "
                    f"the one-call step to ≤ {worst_first:.1e} (max relative difference).")
        if all("first_response_beside_seconds" in r for r in rows):
            besides = [r["first_response_beside_seconds"] / r["one_step_seconds"] for r in rows]
            text.append(f"With the probe {100 * rows[0]['beside_metres']:.0f} cm beside the cut, its reach holds fewer of the "
                        "step's fresh columns (the rest are left to the completion): the first response takes "
                        + ", ".join(f"{r['first_response_beside_solve_columns']:.0f}" for r in rows)
                        + " LU right-hand sides instead of " + ", ".join(f"{r['first_response_solve_columns']:.0f}" for r in rows)
                        + f", and {min(besides):.2g}–{max(besides):.2g} of the one-call step's time (" +
                        ", ".join(f"{a:.2g} at n = {n:,}" for a, n in zip(besides, ns)) + ").")
    text += _goal_text(rows)
    text.append(_load_text(run))
    worst = max(r["agreement"] for r in rows)
    text.append(f"Agreement of the updated table with the refactorisation: ≤ {worst:.1e} (max relative difference).")
    parts = [intro, "![Exact cut-step latency against n](images/cut_latency.png)", _table(rows), " ".join(t for t in text if t)]
    if profiled:
        parts += ["**Where a step's time goes.** Each phase's median over the steps (GreensTableUpdateResult's profile; the "
                  "medians of the phases need not add up to the median step).",
                  "![Where the exact step's time goes](images/cut_latency_profile.png)", _profile_table(rows), _profile_text(rows)]
    return "\n\n".join(parts)
