"""Stability study (h): press depth against tool radius (issue 25, docs/stability.md; bench_stability
--study depth, benchmarks/stability/contact_studies.cpp). Run through ToolContactSolver with the
depth check switched off (ContactDepthLimits::for_studies()).

CSV depth.csv: tool (sphere | punch), depth_over_radius, force (BEM), hertz_force, sneddon_force
(the exact sphere in linear elasticity), linear_force (Boussinesq's punch), contact_elements,
contact_radius_over_radius (farthest contact centroid), sneddon_contact_radius_over_radius,
checked (what bemsurg press and the session do with that tool: ok | warned (depth) | warned (resolution) |
warned (depth and resolution) | refused).
"""

import report_lib as rl

NAME = "stability_h"
TITLE = "(h) Press depth against tool radius"
ORDER = 108


def run(ctx):
    rl.run_stability_study(ctx, NAME, "depth")


def render(ctx):
    s = rl.read_stability_summary(ctx, NAME, "depth")
    rows = rl.read_csv(ctx.part_dir(NAME) / "depth.csv")
    sph = sorted((r for r in rows if r["tool"] == "sphere"), key=lambda r: r["depth_over_radius"])
    pun = sorted((r for r in rows if r["tool"] == "punch"), key=lambda r: r["depth_over_radius"])
    fig, ax = rl.new_figure(7.6, 5.0)
    x = [r["depth_over_radius"] for r in sph]
    ax.plot(x, [r["force"] for r in sph], "o-", color="tab:orange", label="sphere: bemsurg")
    ax.plot(x, [r["hertz_force"] for r in sph], ":", color="tab:orange", label="sphere: Hertz (4/3) E* R^0.5 d^1.5")
    ax.plot(x, [r["sneddon_force"] for r in sph], "--", color="tab:red", label="sphere: exact sphere (Sneddon)")
    xp = [r["depth_over_radius"] for r in pun]
    ax.plot(xp, [r["force"] for r in pun], "s-", color="tab:blue", label="flat punch: bemsurg")
    ax.plot(xp, [r["linear_force"] for r in pun], "--", color="tab:blue", label="flat punch: Boussinesq 2 a E* d")
    ax.axvline(s["max_tool_strain"], color="black", linestyle="-.", label=f"refused beyond d/R = {s['max_tool_strain']:.3g}")
    ax.axvline(s["warn_tool_strain"], color="grey", linestyle="-.", label=f"warned beyond d/R = {s['warn_tool_strain']:.3g}")
    ax.axvline(s["threshold"], color="red", linestyle=":", label=f"Hertz 5 % off the exact sphere: d/R = {s['threshold']:.3g}")
    ax.set(xscale="log", yscale="log", xlabel="depth / tool radius d / R", ylabel="force (E = 1, R = 1)",
           title="Force against press depth")
    ax.legend(fontsize=8)
    rl.save(fig, ctx.image("stability_h_depth"))
    table = ["| d / R | sphere / Sneddon | Hertz / Sneddon | contact radius / R (bemsurg, Sneddon) | sphere: press, session "
             "| punch / Boussinesq | punch: press, session |",
             "|---:|---:|---:|---:|---|---:|---|"]
    for a, b in zip(sph, pun):
        table.append(f"| {a['depth_over_radius']:g} | {a['force'] / a['sneddon_force']:.3f} | {a['hertz_force'] / a['sneddon_force']:.3f} | "
                     f"{a['contact_radius_over_radius']:.2f}, {a['sneddon_contact_radius_over_radius']:.2f} | {a['checked']} | "
                     f"{b['force'] / b['linear_force']:.3f} | {b['checked']} |")
    # A force more than 10 % off its closed form that press and the session would give without a
    # word is what this column exists to catch: say so in the text rather than leave it to the reader.
    silent = [(t, r["depth_over_radius"], r["force"] / ref - 1.0) for t, rs, key in (("sphere", sph, "sneddon_force"),
                                                                                       ("punch", pun, "linear_force"))
              for r in rs for ref in [r[key]] if r["checked"] == "ok" and ref and abs(r["force"] / ref - 1.0) > 0.10]
    table += ["", ("**Unannounced errors:** " + "; ".join(f"{t} at d/R = {d:g} is {100 * e:+.0f} % off with no warning"
                                                           for t, d, e in silent)) if silent else
              "Every press more than 10 % off its closed form is warned or refused by press and the session."]
    lines = [
        f"Swept: {s['parameter']}, on the truncated half-space block (E = 1, ν = 0.3), through the library with the "
        "depth check switched off by ContactDepthLimits::for_studies() (an option for studies; the CLI and the session "
        "keep the default limits).", "",
        "![force against depth / radius](images/stability_h_depth.png)", "",
        f"**Threshold.** {s['threshold_text']}", "",
        f"**Behaviour.** {s['behaviour']}", "",
    ] + table
    return "\n".join(lines)
