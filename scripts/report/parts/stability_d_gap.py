"""Stability study (d): cut gap width against element size (issue 25, docs/stability.md;
bench_stability --study gap, benchmarks/stability/cutting_studies.cpp).

CSV gap.csv, one row per gap ratio: gap_ratio (width / local edge length), equations,
condition_estimate (1-norm, from the LU), displacement_error and traction_error (largest difference
from the refined quadrature, relative to the largest value), gmres_iterations, bicgstab_iterations,
bicg_iterations (block-Jacobi, 1e-10, x0 = 0), all_converged, refused (the cutter's reason where
its other checks refused the groove; empty otherwise).
"""

import report_lib as rl

NAME = "stability_d"
TITLE = "(d) Cut gap width against element size"
ORDER = 104
STUDY = "gap"


def run(ctx):
    rl.run_stability_study(ctx, NAME, STUDY)


def render(ctx):
    rows = rl.read_csv(ctx.part_dir(NAME) / "gap.csv")
    s = rl.read_stability_summary(ctx, NAME, STUDY)
    done = sorted((r for r in rows if not r["refused"]), key=lambda r: r["gap_ratio"])
    x = [r["gap_ratio"] for r in done]
    fig, axes = rl.plt.subplots(1, 3, figsize=(13.0, 4.2), dpi=110)
    panels = [
        ("1-norm condition estimate of A*", [("condition_estimate", "A* (default quadrature)")], s["uncut_condition"]),
        ("difference from the refined quadrature", [("displacement_error", "displacement"), ("traction_error", "traction")],
         s["uncut_error"]),
        ("Krylov iterations to 1e-10 (x0 = 0)", [("gmres_iterations", "GMRES"), ("bicgstab_iterations", "BiCGStab"),
                                                 ("bicg_iterations", "BiCG")], None),
    ]
    for ax, (title, series, uncut) in zip(axes, panels):
        ax.grid(True, which="both", alpha=0.3)
        for i, (key, label) in enumerate(series):
            ax.plot(x, [r[key] for r in done], marker=rl.MARKERS[i], label=label)
        if uncut:
            ax.axhline(uncut, color="grey", ls=":", label="uncut body")
        if key.endswith("error"):
            ax.axhline(s["tolerance"], color="red", ls="--", lw=1, label=f"tolerance {s['tolerance']:g}")
        ax.axvline(s["threshold"], color="black", ls="--", lw=1.2, label=f"kMinimumGapRatio = {s['threshold']:g}")
        ax.set_xscale("log")
        if not title.startswith("Krylov"):
            ax.set_yscale("log")
        ax.invert_xaxis()
        ax.set_xlabel("gap width / local edge length")
        ax.set_title(title, fontsize=9)
        ax.legend(fontsize=7)
    rl.save(fig, ctx.image("stability_d_gap"))

    lines = [
        f"Swept: {s['parameter']}, from the widest groove the cutter accepts to 1e-3 (below the limit the gap check is "
        "switched off with the option meant for studies, `CutOptions::allow_narrow_gap_for_studies`). The body is "
        "bench_cut's soft box on its base under gravity (docs/cutting.md); the reference is the same mesh with a refined "
        "quadrature (far 8, mid 4, order 10, depth 18, polar 20); no closed form applies to a cut box. Dotted: the uncut "
        "body's own figures.", "",
        "![condition, error and Krylov iterations against the gap ratio](images/stability_d_gap.png)", "",
        f"**Threshold.** {s['threshold_text']}", "",
        f"**Behaviour.** {s['behaviour']}", "",
        "| gap / edge | equations | condition estimate | displacement difference | GMRES | BiCGStab | BiCG |",
        "|---|---|---|---|---|---|---|"]
    # The uncut body first: the baseline the threshold text compares the cut ones with.
    its = s.get("uncut_iterations", ["", "", ""])
    lines.append(f"| uncut (baseline) | {s.get('uncut_equations', '–')} | {s['uncut_condition']:.2e} | {s['uncut_error']:.2e} | "
                 f"{its[0]} | {its[1]} | {its[2]} |")
    for r in sorted(rows, key=lambda r: -r["gap_ratio"]):
        if r["refused"]:
            lines.append(f"| {r['gap_ratio']:g} | – | – | refused by the cutter: {r['refused']} | | | |")
        else:
            lines.append(f"| {r['gap_ratio']:g} | {r['equations']} | {r['condition_estimate']:.2e} | "
                         f"{r['displacement_error']:.2e} | {r['gmres_iterations']} | {r['bicgstab_iterations']} | "
                         f"{r['bicg_iterations']} |")
    return "\n".join(lines)
