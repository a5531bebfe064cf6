"""Stability study (g): thin parts and tool size against element size (issue 25, docs/stability.md;
bench_stability --study thin, benchmarks/stability/contact_studies.cpp).

CSV thin_slab.csv: case (bending: Saint-Venant's pure bending of a plate, the exact field on its
ends, error of the end moment; compression: a slab on rollers pressed over its whole top, against
uniaxial strain), thickness_over_h, half_cells, elements, force_ratio, error, deflection_error
(bending: relative L2 of u_z over the faces), thin_elements (find_thin_elements' count).
CSV tool_size.csv: tool (punch | sphere), radius_over_h (contact radius / element size), elements,
contact_elements, force_ratio (against Boussinesq / Hertz), error.
"""

import report_lib as rl

NAME = "stability_g"
TITLE = "(g) Thin parts and tool size against element size"
ORDER = 107


def run(ctx):
    rl.run_stability_study(ctx, NAME, "thin")


def render(ctx):
    d = ctx.part_dir(NAME)
    s = rl.read_stability_summary(ctx, NAME, "thin")
    slab, tool = rl.read_csv(d / "thin_slab.csv"), rl.read_csv(d / "tool_size.csv")
    fig, axes = rl.plt.subplots(1, 2, figsize=(12.0, 4.6), dpi=110)
    ax = axes[0]
    ax.grid(True, which="both", alpha=0.3)
    for case, key, label, m in (("bending", "error", "bent plate: end moment", "o"),
                                ("bending", "deflection_error", "bent plate: deflection (L2)", "s"),
                                ("compression", "error", "compressed slab: force", "^")):
        pts = sorted((r["thickness_over_h"], r[key]) for r in slab if r["case"] == case and r[key] is not None)
        ax.plot([p[0] for p in pts], [max(p[1], 1e-6) for p in pts], marker=m, label=label)
    ax.axhline(0.1, color="grey", linestyle=":", label="10 %")
    if s["threshold"] is not None:
        ax.axvline(s["threshold"], color="red", linestyle="--", label=f"10 % point t/h = {s['threshold']:.3g}")
    ax.axvline(s["warning_ratio"], color="black", linestyle="-.", label=f"thin-part warning below t/h = {s['warning_ratio']:.3g}")
    ax.set(xscale="log", yscale="log", xlabel="thickness / element size t / h", ylabel="relative error",
           title="Thin parts (constant elements)")
    ax.legend(fontsize=8)
    ax = axes[1]
    ax.grid(True, which="both", alpha=0.3)
    for t, m, c in (("punch", "o", "tab:blue"), ("sphere", "s", "tab:orange")):
        pts = sorted((r["radius_over_h"], r["error"]) for r in tool if r["tool"] == t and r["error"] is not None)
        ax.plot([p[0] for p in pts], [max(p[1], 1e-6) for p in pts], marker=m, color=c, label=f"{t} against "
                + ("Boussinesq" if t == "punch" else "Hertz"))
        ax.axvline(s[f"{t}_limit"], color=c, linestyle="--", label=f"{t}: warning below {s[f'{t}_limit']:.3g}")
    ax.axhline(0.1, color="grey", linestyle=":", label="10 %")
    ax.set(xscale="log", yscale="log", xlabel="contact radius / element size a / h", ylabel="force error",
           title="Tool size against element size")
    ax.legend(fontsize=8)
    rl.save(fig, ctx.image("stability_g_thin"))

    rows = ["| t / h | bent plate: moment error | deflection error | compressed slab: force error | thin elements flagged |",
            "|---:|---:|---:|---:|---:|"]
    comp = {r["thickness_over_h"]: r["error"] for r in slab if r["case"] == "compression"}
    for r in sorted((r for r in slab if r["case"] == "bending"), key=lambda r: -r["thickness_over_h"]):
        c = comp.get(r["thickness_over_h"])
        rows.append(f"| {r['thickness_over_h']:g} | {100 * r['error']:.3g} % | {100 * r['deflection_error']:.3g} % | "
                    + (f"{100 * c:.2g} %" if c is not None else "—") + f" | {r['thin_elements']:g} |")
    lines = [
        f"Swept: {s['parameter']}. The plate is meshed with spacing h = 1 on its faces and max(1, t/h) layers "
        "through its thickness; the tools press the truncated half-space block of the contact-accuracy study "
        "(top spacing h near the axis), punch of radius a, sphere R = 20 with Hertz contact radius a.", "",
        "![force error against t/h and a/h](images/stability_g_thin.png)", "",
        f"**Threshold.** {s['threshold_text']}", "",
        f"**Behaviour.** {s['behaviour']}", "",
    ] + rows
    return "\n".join(lines)
