"""Feeling through a cut (issue 26; docs/haptics.md, "Feeling through a cut"): a sphere probe held
3 mm deep on the liver-like organ while a 4-step cut runs 10 mm beside it, before (the cut step
on the simulation thread, the new model switched in at once, background work on every core) and
after (the step on a background thread, the models blended, background work on cores - 1 threads,
SCHED_FIFO asked for), quiet and (full run) beside one busy thread per core, with the empty loop
as the rate baseline (benchmarks/bench_cut_continuity.cpp).

Data: DIR/haptic_cut/bench_cut_continuity.json (per run: configuration, load, rate_hz,
overruns_per_s, min_delivered_force_ratio, max_tick_change_fraction, max_force_jump_fraction,
watchdog_ticks, cuts, cut_step_seconds (to the first response), cut_complete_seconds; cut_times,
blend_s, stale_after_s; step_profile, full runs only: per cut step of the script without the loop,
surface, integration, solve (and right-hand sides), correction, snapshot, gemm and finish seconds,
first_response_seconds, complete_seconds) and
trace_<configuration>_<load>.csv (time, model, delivered, watchdog_gain, blend_weight,
model_version: the probe, every tick).
"""

import json

import report_lib as rl

NAME = "haptic_cut"
TITLE = "Feeling through a cut: the force while cut steps compute"
ORDER = 61

TARGET_RATIO, TARGET_CHANGE, TARGET_RATE = 0.8, 0.05, 990.0  # issue 26, "done means"
COLOURS = {"before": "tab:red", "after": "tab:blue"}


def run(ctx):
    d = ctx.part_dir(NAME)
    args = [ctx.program("bench_cut_continuity"), "--csv-dir", d, "--json", d / "bench_cut_continuity.json"]
    stdout, _ = ctx.run(args + (["--quick"] if ctx.quick else []), NAME, timeout=900)
    (d / "bench_cut_continuity.txt").write_text(stdout)


def _traces(ctx, j, loads, zoom):
    """One panel per load: the probe's delivered force before and after, the model force dashed,
    each cut step's start marked; zoom: a window around the last (longest) step."""
    d = ctx.part_dir(NAME)
    fig, axes = rl.plt.subplots(1, len(loads), figsize=(6.0 * len(loads), 4.2), dpi=110, squeeze=False)
    cut_times = j["cut_times"]
    for ax, load in zip(axes[0], loads):
        for cfg in ("before", "after"):
            rows = rl.read_csv(d / f"trace_{cfg}_{load}.csv")
            if zoom:
                rows = [r for r in rows if cut_times[-1] - 0.2 <= r["time"] <= cut_times[-1] + 1.0]
            t = [r["time"] for r in rows]
            ax.plot(t, [1e3 * r["delivered"] for r in rows], color=COLOURS[cfg], lw=1.4, label=f"{cfg}: delivered")
            ax.plot(t, [1e3 * r["model"] for r in rows], color=COLOURS[cfg], lw=0.9, ls="--", alpha=0.8, label=f"{cfg}: contact model")
        for k, c in enumerate(cut_times):
            if not zoom or c >= cut_times[-1] - 0.2:
                ax.axvline(c, color="gray", lw=0.8, ls=":", label="cut step starts" if k == len(cut_times) - 1 else None)
        ax.set_xlabel("session time (s)")
        ax.set_ylabel("probe force (mN)")
        ax.set_title(f"{load}{' (one busy thread per core beside it)' if load == 'loaded' else ''}"
                     f"{': the last cut step' if zoom else ''}", fontsize=9)
        ax.grid(True, alpha=0.3)
        ax.legend(fontsize=7, loc="lower left")
    name = "haptic_cut_zoom" if zoom else "haptic_cut_trace"
    rl.save(fig, ctx.image(name))
    return name


def _verdict(r, empty):
    met = [r["min_delivered_force_ratio"] >= TARGET_RATIO, r["max_tick_change_fraction"] <= TARGET_CHANGE,
           r["rate_hz_median"] >= TARGET_RATE]
    if empty is not None:
        met.append(r["overruns_per_s_median"] <= empty["overruns_per_s_median"] + 1e-9)
    return "met" if all(met) else "**not met**"


def _table(j):
    """One row per configuration and load: medians over the repetitions of the rate and the overruns
    per second, the worst felt-force figures; every run's cut steps made is checked separately."""
    rows = j["summary"]
    empty = {r["load"]: r for r in rows if r["configuration"] == "empty"}
    lines = ["| configuration | load | runs | rate, median (min) Hz | overruns / s, median | delivered / model, min | "
             "largest tick change | cut step to first response, median (min–max over the runs' steps) | "
             "to the complete table, median | targets |",
             "|---|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        target = "baseline" if r["configuration"] == "empty" else _verdict(r, empty.get(r["load"]))
        step = (rl.spread_text(r["cut_step_seconds_median"], r.get("cut_step_seconds_min"), r.get("cut_step_seconds_max"),
                               r.get("cut_steps")).replace(" runs)", " steps)")
                if r["configuration"] != "empty" else "–")
        complete = (rl.seconds_text(r["cut_complete_seconds_median"])
                    if r["configuration"] != "empty" and "cut_complete_seconds_median" in r else "–")
        lines.append(f"| {r['configuration']} | {r['load']} | {r['runs']} | {r['rate_hz_median']:.1f} ({r['rate_hz_min']:.1f}) | "
                     f"{r['overruns_per_s_median']:.2f} | {100 * r['min_delivered_force_ratio']:.1f} % | "
                     f"{100 * r['max_tick_change_fraction']:.2f} % | {step} | {complete} | {target} |")
    cuts = [r["cuts"] for r in j["runs"] if r["configuration"] != "empty"]
    prio = sorted({r["realtime_priority"] for r in j["runs"] if r["configuration"] == "after"})
    made = f"all {max(cuts)}" if min(cuts) == max(cuts) else f"{min(cuts)} to {max(cuts)}"
    lines += ["", f"Every run with a cut made {made} of its 4 cut steps; the haptic thread of the `after` runs got SCHED_FIFO "
              f"priority {', '.join(str(p) for p in prio)} (0: refused). Overruns per second are medians of {rows[0]['runs']} "
              "runs of 3.2 s: one overrun more or less in a run moves them by 0.3; compare them with the empty loop's "
              "spread (`bench_cut_continuity.json`, `runs`)."]
    return "\n".join(lines)


def _profile(j):
    """Where a session's cut step goes (issue 39): the script's steps without the loop, on the
    session's background thread budget (bench_cut_continuity's "step_profile", full runs only)."""
    p = j.get("step_profile") or {}
    if not p.get("steps"):
        return ""
    lines = [f"Where a cut step of this session goes, the script's steps taken by the session's cut entry point "
             f"without the loop beside them, on {p['threads']} thread(s) as the session's background work runs "
             f"(first response over the region elements within {1e3 * p['reach_metres']:.0f} mm of the probe; "
             "seconds from the request; `bench_cut_continuity.json`, `step_profile`):", "",
             "| step | n | reach / region | surface | integration | LU solves (right-hand sides: first response / all) "
             "| accumulated rank | table | first response | complete |",
             "|---|---|---|---|---|---|---|---|---|---|"]
    for k, r in enumerate(p["steps"]):
        table = r["snapshot_seconds"] + r["gemm_seconds"] + r["finish_seconds"]
        lines.append(f"| {k + 1} | {r['equations']:,} | {r['reach_elements']} / {r['region_elements']} | "
                     f"{r['surface_seconds']:.3f} | {r['integration_seconds']:.3f} | {r['solve_seconds']:.3f} "
                     f"({r['first_response_solve_columns']} / {r['solve_columns']}) | {r['correction_seconds']:.3f} | "
                     f"{table:.3f} | {r['first_response_seconds']:.3f} | {r['complete_seconds']:.3f} |")
    whole = all(r["reach_elements"] == r["region_elements"] for r in p["steps"])
    lines += ["", ("The reach covers the whole operating region here, so the first response is the complete table (made "
                   "once). " if whole else "") +
              "The session's `cut_step_seconds` above add what the loop beside the step takes from it (the haptic "
              "thread's core, memory bandwidth, the frame's field)."]
    return "\n".join(lines)


def render(ctx):
    d = ctx.part_dir(NAME)
    j = json.loads((d / "bench_cut_continuity.json").read_text())
    loads = sorted({r["load"] for r in j["runs"] if r["configuration"] != "empty"}, key=lambda x: x != "quiet")
    trace = _traces(ctx, j, loads, zoom=False)
    zoom = _traces(ctx, j, loads, zoom=True)
    after = [r for r in j["summary"] if r["configuration"] == "after"]
    before = [r for r in j["summary"] if r["configuration"] == "before"]
    worst_before = min(r["min_delivered_force_ratio"] for r in before)
    worst_after = min(r["min_delivered_force_ratio"] for r in after)
    return "\n".join([
        f"A sphere probe (radius 15 mm) is held 3 mm deep on the liver-like organ of `examples/scenes/liver.json` "
        f"({j['elements']:,} elements, a table of {j['table_columns']:,} columns) while a 4-step cut runs 10 mm beside it "
        f"(`examples/liver-cut-session.json`), in real time on {j['cores']} cores. **Before**: each cut step on the "
        f"simulation thread, which stops beating the heartbeat while it computes (the watchdog takes the simulation as dead "
        f"after {j['stale_after_s']} s), the new model switched in at once, background work on every core. **After**: the "
        f"step on a background thread, the old model blended into the new over {1e3 * j['blend_s']:.0f} ms, background work "
        f"on cores − 1 threads, SCHED_FIFO asked for. Smallest delivered / model force ratio: {100 * worst_before:.0f} % "
        f"before, {100 * worst_after:.0f} % after.",
        "",
        f"![probe force through the cut, before and after](images/{trace}.png)",
        "",
        f"![the last cut step](images/{zoom}.png)",
        "",
        _table(j),
        "",
        _profile(j),
        "",
        f"Targets (issue 26): delivered force ≥ {100 * TARGET_RATIO:.0f} % of the model's, no tick-to-tick change above "
        f"{100 * TARGET_CHANGE:.0f} %, ≥ {TARGET_RATE:.0f} Hz, all 4 cut steps made, and no more overruns per second than the "
        "empty loop under the same load (the `empty` rows, measured in the same process). The ratio and the change are over "
        "the ticks where the model force is at least 10 % of its peak (`haptics/felt_force.hpp`); the model-force jump is the "
        "older metric, blind to a fade. The traces are each configuration's first run.",
    ])
