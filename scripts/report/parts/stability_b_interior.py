"""Stability study (b): interior points approaching the surface (issue 25, docs/stability.md;
bench_stability --study interior, benchmarks/stability/geometry_studies.cpp).

CSV stability_interior.csv, one row per point and evaluation: distance_over_h (distance to the
surface / longest edge h of the nearest element), target (face: below an element's centroid, edge:
below the midpoint of an element edge, vertex: below a mesh vertex), quadrature (default |
max_depth_20), data (bem: the solved Kelvin problem; exact_traces: the exact field at the centroids,
full sweep only; rigid: a rigid translation, exact stress 0), refused_displacement and refused_stress
(1 where bemsurg refuses the point for that quantity), displacement_error and stress_error (relative
to the exact value; for the rigid motion relative to |c| and E|c|).
"""

import report_lib as rl

NAME = "stability_b"
TITLE = "(b) Interior points approaching the surface"
ORDER = 102
STUDY = "interior"
TARGETS = [("face", "below a centroid"), ("edge", "below an edge midpoint"), ("vertex", "below a vertex")]


def run(ctx):
    rl.run_stability_study(ctx, NAME, STUDY)


def _series(rows, target, quadrature, data, key):
    pts = sorted((r["distance_over_h"], r[key]) for r in rows
                 if r["target"] == target and r["quadrature"] == quadrature and r["data"] == data)
    return [p[0] for p in pts], [p[1] for p in pts]


def render(ctx):
    rows = rl.read_csv(ctx.part_dir(NAME) / "stability_interior.csv")
    s = rl.read_stability_summary(ctx, NAME, STUDY)
    fig, axes = rl.plt.subplots(1, 3, figsize=(13.5, 4.4), dpi=110, sharey=True)
    for ax, (target, where) in zip(axes, TARGETS):
        ax.grid(True, which="both", alpha=0.3)
        for i, (quad, data, key, label, style) in enumerate([
                ("default", "bem", "displacement_error", "u, BEM solution", "-"),
                ("default", "bem", "stress_error", "stress, BEM solution", "-"),
                ("max_depth_20", "bem", "stress_error", "stress, BEM, max_depth 20", ":"),
                ("default", "rigid", "displacement_error", "u, rigid motion (quadrature only)", "--"),
                ("default", "rigid", "stress_error", "stress, rigid motion (quadrature only)", "--")]):
            x, y = _series(rows, target, quad, data, key)
            y = [max(v, 1e-12) for v in y]
            ax.plot(x, y, marker=rl.MARKERS[i % len(rl.MARKERS)], ls=style, label=label, ms=4)
        ax.axvline(s["displacement_limit"], color="black", ls="--", lw=1.1,
                   label=f"displacement limit {s['displacement_limit']:.3g} h")
        ax.axvline(s["stress_limit"], color="red", ls="--", lw=1.1, label=f"stress limit {s['stress_limit']:g} h")
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.invert_xaxis()
        ax.set_xlabel("distance / element size h")
        ax.set_title(f"approaching {where}", fontsize=9)
    axes[0].set_ylabel("relative error")
    axes[0].legend(fontsize=7)
    rl.save(fig, ctx.image("stability_b_interior"))

    lines = [
        f"Swept: {s['parameter']}, on the Kelvin box of tests/test_bem_interior.cpp ({s['elements']} elements, "
        f"h = {s['h']:.3g}; a point force above a 2 × 1.2 × 1.2 box, the exact displacement held on the lower half). "
        "Solid lines: the BEM solution with the default quadrature, evaluated below each limit with the refusal "
        "switched off (`InteriorEvaluator::allow_points_too_close_for_studies`); dotted: the same with max_depth 20; "
        "dashed: a rigid translation, whose exact stress is zero, so its curve is the quadrature's error alone.", "",
        "![relative error of displacement and stress against distance / h](images/stability_b_interior.png)", "",
        f"**Threshold.** {s['threshold_text']}", "",
        f"**Behaviour.** {s['behaviour']}", "",
        "| d / h | target | u error (BEM) | stress error (BEM) | stress error (max_depth 20) | bemsurg |",
        "|---|---|---|---|---|---|"]
    for r in sorted((r for r in rows if r["quadrature"] == "default" and r["data"] == "bem"),
                    key=lambda r: (-r["distance_over_h"], r["target"])):
        if r["target"] != "vertex":
            continue
        deep = [q for q in rows if q["quadrature"] == "max_depth_20" and q["data"] == "bem" and q["target"] == "vertex"
                and q["distance_over_h"] == r["distance_over_h"]][0]
        verdict = "refuses u and stress" if r["refused_displacement"] else "refuses stress" if r["refused_stress"] else "evaluates"
        lines.append(f"| {r['distance_over_h']:.2g} | vertex | {r['displacement_error']:.2e} | {r['stress_error']:.2e} | "
                     f"{deep['stress_error']:.2e} | {verdict} |")
    return "\n".join(lines)
