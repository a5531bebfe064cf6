"""Study (i) of issue 25, non-uniform meshes (bench_stability --study grading; docs/stability.md,
docs/graded.md#safe-gradings): the clamped 1 x 1 x 3 box under a Kelvin load from a point above it on
its mirror plane (exact solution known), on uniform boxes, boxes refined red-green in various zones
and graded Gmsh meshes fine in one half, with and without the clamped face refined too.

CSV stability_i_strategies.csv: strategy, element_type, base_divisions, level, elements,
max_neighbour_size_ratio, support_size_ratio, displacement_error, traction_error (relative L2).
CSV stability_i_ratio.csv: outside_edge_length, element_type, rule, elements,
max_neighbour_size_ratio, support_size_ratio, displacement_error, traction_error.
Another element type (linear elements, issue 27) is one more value of element_type: one more series.
"""

import report_lib as rl

NAME = "stability_i"
TITLE = "(i) Non-uniform meshes"
ORDER = 109
STUDY = "grading"


def run(ctx):
    rl.run_stability_study(ctx, NAME, STUDY)


def _pct(x):
    return "–" if x is None else f"{100 * x:.2f} %"


def _series(rows, key):
    out = {}
    for r in rows:
        out.setdefault(key(r), []).append(r)
    return out


def render(ctx):
    d = ctx.part_dir(NAME)
    s = rl.read_stability_summary(ctx, NAME, STUDY)
    rows = rl.read_csv(d / "stability_i_strategies.csv")
    ratio_rows = rl.read_csv(d / "stability_i_ratio.csv")

    fig, ax = rl.new_figure(7.2, 4.8)
    series = _series([r for r in rows if r["base_divisions"] == 2 or r["strategy"] == "uniform"],
                     lambda r: (r["strategy"], r["element_type"]))
    for i, ((strategy, etype), pts) in enumerate(sorted(series.items())):
        pts = sorted(pts, key=lambda r: r["elements"])
        ax.plot([p["elements"] for p in pts], [p["displacement_error"] for p in pts], marker=rl.MARKERS[i % len(rl.MARKERS)],
                lw=2.2 if strategy == "uniform" else 1.2, color="black" if strategy == "uniform" else None,
                label=f"{strategy} ({etype})", alpha=0.85)
    for j, ((rule, etype), pts) in enumerate(sorted(_series(ratio_rows, lambda r: (r["rule"], r["element_type"])).items())):
        pts = sorted(pts, key=lambda r: r["elements"])
        ax.plot([p["elements"] for p in pts], [p["displacement_error"] for p in pts], ls=":", marker="o" if j == 0 else "s",
                markerfacecolor="none", label=f"graded (Gmsh), {rule} ({etype})")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("elements")
    ax.set_ylabel("displacement error (relative L2)")
    ax.set_title("clamped box, Kelvin load: error per refinement strategy (red-green: levels 1, 2, ... of base 2×2×6)", fontsize=8)
    ax.legend(fontsize=6.5)
    rl.save(fig, ctx.image("stability_i_strategies"))

    fig, (ax0, ax) = rl.plt.subplots(1, 2, figsize=(11.5, 4.6), dpi=110, sharey=True)
    for a, key, label in ((ax0, "max_neighbour_size_ratio", "largest neighbouring size ratio (MeshQuality)"),
                          (ax, "support_size_ratio", "support size ratio (held elements, p90 / all elements, p10)")):
        a.grid(True, which="both", alpha=0.3)
        for i, (rule, pts) in enumerate(sorted(_series(ratio_rows, lambda r: (r["rule"], r["element_type"])).items())):
            pts = sorted(pts, key=lambda r: r[key])
            a.plot([p[key] for p in pts], [p["displacement_error"] for p in pts], "o" if i == 0 else "s",
                   label=f"graded, {rule[0]} ({rule[1]})")
        rg = [r for r in rows if r["strategy"].startswith("red-green")]
        a.plot([r[key] for r in rg], [r["displacement_error"] for r in rg], "k^", alpha=0.5, label="red-green meshes")
        uni = [r for r in rows if r["strategy"] == "uniform"]
        a.plot([r[key] for r in uni], [r["displacement_error"] for r in uni], "kx", label="uniform boxes")
        a.set_yscale("log")
        a.set_xlabel(label)
    ax0.set_ylabel("displacement error (relative L2)")
    ax0.set_title("the neighbouring size ratio does not sort the errors", fontsize=9)
    ax.set_title("right of the limit: worse than the rule-following mesh of the same sizes", fontsize=9)
    ax.axvline(s["limit"], color="red", ls="--", label=f"limit kMaxSupportSizeRatio = {s['limit']}")
    ax.axvline(s["threshold"], color="grey", ls=":", label=f"measured safe ratio {s['threshold']:.2f}")
    ax.legend(fontsize=7)
    rl.save(fig, ctx.image("stability_i_ratio"))

    lines = [
        "A 1 × 1 × 3 box clamped at its top (the exact Kelvin displacement prescribed there, the exact traction "
        "everywhere else) under Kelvin's point force at (0, 0.25, 3.5), half a unit above the top on the mirror plane "
        "x = 0. Swept: the refinement strategy (uniform boxes; red-green local refinement, `mesh/red_green_refinement.hpp`, "
        "of one half, the mirror half, both, the clamped face, a half with the clamped face; graded Gmsh meshes fine in "
        "the half x < 0, coarser outside, with and without the clamped face meshed finely too) and the support size "
        "ratio (how much coarser the held elements are than the finest). Constant elements; linear elements (issue 27) "
        "will be one more series on the same meshes.", "",
        "![error against elements per strategy](images/stability_i_strategies.png)", "",
        "![error against the neighbouring size ratio and the support size ratio](images/stability_i_ratio.png)", "",
        f"On the 2 × 2 × 6 base (displacement error {_pct(s.get('base_error'))}), refining one half raised the error "
        f"to {_pct(s.get('half_error'))} (the mirror half: {_pct(s.get('mirror_half_error'))}; this base is "
        f"mirror-symmetric), refining the half with the clamped face gave {_pct(s.get('half_and_supported_error'))}, "
        f"both halves {_pct(s.get('both_error'))}."]
    if "odd_half_error" in s:
        lines[-1] += (f" On the 3 × 3 × 9 base, which is not mirror-symmetric, the two halves differ: "
                      f"{_pct(s['odd_base_error'])} → {_pct(s['odd_half_error'])} (x < 0) and "
                      f"{_pct(s['odd_mirror_half_error'])} (x > 0).")
    lines += ["", "Per element, no local refinement beat the uniform boxes here: refining the clamped face together with "
              "the half brings a locally refined mesh back to the uniform curve, refining the half alone stays well "
              "above it. The ratio is necessary, not sufficient: refining only the clamped face (ratio 1, the "
              "finest elements are the held ones) is also worse than the base at first, and improves with further levels.",
              "", f"**Threshold:** {s['threshold_text']}.", "", f"**Behaviour:** {s['behaviour']}.", "",
              "| graded, outside edge length | rule | elements | support size ratio | displacement error |",
              "|---|---|---|---|---|"]
    for r in ratio_rows:
        lines.append(f"| {r['outside_edge_length']} | {r['rule']} | {r['elements']} | {r['support_size_ratio']:.2f} | "
                     f"{_pct(r['displacement_error'])} |")
    return "\n".join(lines) + "\n"
