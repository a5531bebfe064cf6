"""Stability study (c): sliver triangles (issue 25, docs/stability.md; bench_stability --study sliver,
benchmarks/stability/geometry_studies.cpp and tests/support/studies/geometry_setup.hpp).

CSV stability_sliver.csv, one row per mesh and quadrature: family (needle: the Kelvin box with a
slab of width eps around x = 0, whose faces are needles; cap: the box with every valence-4 vertex of
the top and bottom faces moved to height eps x diagonal over a cell diagonal), eps, aspect_ratio
(the mesh's largest, mesh_quality.hpp), min_angle_degrees, elements, quadrature (default |
max_depth_20), condition (2-norm condition number of A*), displacement_error and traction_error
(relative L2 over the solved components), sliver_displacement_error and sliver_traction_error (the
same over the slivers only), interior_displacement_error and interior_stress_error (four interior
points of tests/test_bem_interior.cpp).
"""

import report_lib as rl

NAME = "stability_c"
TITLE = "(c) Sliver triangles"
ORDER = 103
STUDY = "sliver"
FAMILIES = [("needle", "band of needles"), ("cap", "flat caps")]


def run(ctx):
    rl.run_stability_study(ctx, NAME, STUDY)


def _series(rows, family, quadrature, key):
    pts = sorted((r["aspect_ratio"], r[key]) for r in rows if r["family"] == family and r["quadrature"] == quadrature)
    return [p[0] for p in pts], [p[1] for p in pts]


def render(ctx):
    rows = rl.read_csv(ctx.part_dir(NAME) / "stability_sliver.csv")
    s = rl.read_stability_summary(ctx, NAME, STUDY)
    fig, axes = rl.plt.subplots(1, 3, figsize=(13.5, 4.4), dpi=110)
    panels = [("relative error (whole mesh)", [("traction_error", "traction"), ("displacement_error", "displacement"),
                                               ("interior_stress_error", "interior stress")]),
              ("relative error on the slivers", [("sliver_traction_error", "traction"),
                                                 ("sliver_displacement_error", "displacement")]),
              ("condition number of A*", [("condition", "cond(A*)")])]
    for ax, (title, series) in zip(axes, panels):
        ax.grid(True, which="both", alpha=0.3)
        i = 0
        for family, label in FAMILIES:
            for key, what in series:
                x, y = _series(rows, family, "default", key)
                pos = [(a, b) for a, b in zip(x, y) if b and b > 0]
                if pos:
                    ax.plot([p[0] for p in pos], [p[1] for p in pos], marker=rl.MARKERS[i % len(rl.MARKERS)],
                            ls="-" if family == "needle" else "--", label=f"{what}, {label}", ms=4)
                i += 1
            if title.startswith("relative error (whole"):
                x, y = _series(rows, family, "max_depth_20", "traction_error")
                if x:
                    ax.plot(x, y, ls=":", color="grey", label=f"traction, {label}, max_depth 20")
        ax.axvline(s["warning_aspect_ratio"], color="orange", ls="--", lw=1.1,
                   label=f"warning {s['warning_aspect_ratio']:g}")
        ax.axvline(s["refusal_aspect_ratio"], color="red", ls="--", lw=1.1, label=f"refused above {s['refusal_aspect_ratio']:g}")
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel("largest aspect ratio (1: equilateral)")
        ax.set_title(title, fontsize=9)
        ax.legend(fontsize=6)
    rl.save(fig, ctx.image("stability_c_sliver"))

    lines = [
        f"Swept: {s['parameter']}, on the Kelvin box of tests/test_bem_interior.cpp (a point force above a 2 × 1.2 × 1.2 "
        "box, the exact displacement held on the lower half, the exact traction elsewhere), made of needles (a slab "
        "of width eps around x = 0 puts a band of needles round the box) or of flat caps (vertices of the top and bottom "
        "faces moved towards a cell diagonal); both stay closed and flat. The meshes beyond the refusal limit are "
        "assembled directly, without `require_valid_mesh`.", "",
        "![error and condition number against the aspect ratio](images/stability_c_sliver.png)", "",
        f"**Threshold.** {s['threshold_text']}", "",
        f"**Behaviour.** {s['behaviour']}", "",
        "| family | aspect ratio | cond(A*) | traction error | on the slivers | interior stress error |",
        "|---|---|---|---|---|---|"]
    for family, _ in FAMILIES:
        for r in sorted((r for r in rows if r["family"] == family and r["quadrature"] == "default"),
                        key=lambda r: r["aspect_ratio"]):
            lines.append(f"| {family} | {r['aspect_ratio']:.3g} | {r['condition']:.3g} | {r['traction_error']:.3g} | "
                         f"{r['sliver_traction_error']:.3g} | {r['interior_stress_error']:.3g} |")
    return "\n".join(lines)
