"""Stability study (e): GMRES restart length, BiCG and BiCGStab breakdowns (issue 25,
docs/stability.md). bench_stability --study krylov solves the Kelvin box with displacement
prescribed everywhere (cond2(A*) grows as 1/(0.5 - nu), study (a)) for several n and nu by GMRES(m)
over restart lengths m (0: full GMRES), BiCGStab and BiCG, with block-Jacobi and without a
preconditioner, and writes stability_e_krylov.csv: n, poisson_ratio, preconditioner, method,
restart, status, breakdown (the vanished quantity, quoted), iterations, restarts, relative_residual.
"""

import report_lib as rl

NAME = "stability_e"
TITLE = "(e) GMRES restart length, BiCG and BiCGStab breakdowns"
ORDER = 105
STUDY = "krylov"


def run(ctx):
    rl.run_stability_study(ctx, NAME, STUDY)


def render(ctx):
    s = rl.read_stability_summary(ctx, NAME, STUDY)
    rows = rl.read_csv(ctx.part_dir(NAME) / "stability_e_krylov.csv")
    gm = [r for r in rows if r["method"] == "gmres"]
    m_max = max(r["restart"] for r in gm)
    full_at = 2 * m_max  # full GMRES drawn at the right of the swept restart lengths
    bi_at = {"bicgstab": 4 * m_max, "bicg": 8 * m_max}  # then BiCGStab (x) and BiCG (+)

    def x_of(r):
        return r["restart"] if r["restart"] > 0 else full_at

    fig, axes = rl.plt.subplots(1, 2, figsize=(12.5, 4.4), dpi=110, sharey=True)
    for ax, pk in zip(axes, ("block_jacobi", "none")):
        ax.grid(True, which="both", alpha=0.3)
        series = sorted({(r["n"], r["poisson_ratio"]) for r in gm if r["preconditioner"] == pk})
        for i, (n, nu) in enumerate(series):
            pts = sorted((x_of(r), r["iterations"], r["status"]) for r in gm
                         if r["preconditioner"] == pk and r["n"] == n and r["poisson_ratio"] == nu)
            ax.plot([p[0] for p in pts], [p[1] for p in pts], marker=rl.MARKERS[i % len(rl.MARKERS)], color=f"C{i}",
                    label=f"n = {n}, ν = {nu:g}")
            # BiCGStab and BiCG on the same system, at their own places right of full GMRES.
            for x_bi, method, mk in ((bi_at["bicgstab"], "bicgstab", "x"), (bi_at["bicg"], "bicg", "+")):
                for r in rows:
                    if r["method"] == method and r["preconditioner"] == pk and r["n"] == n and r["poisson_ratio"] == nu:
                        ax.scatter([x_bi], [r["iterations"]], marker=mk, color=f"C{i}", s=40, zorder=4)
                        pts.append((x_bi, r["iterations"], r["status"]))
            bad = [p for p in pts if p[2] != "converged"]
            if bad:
                ax.scatter([p[0] for p in bad], [p[1] for p in bad], s=120, facecolors="none", edgecolors="red", zorder=5)
        ax.axvline(s["threshold"], color="red", ls="--", label="converges everywhere (block-Jacobi) from m = %d" % s["threshold"])
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel("GMRES restart length m, full GMRES; BiCGStab (x) and BiCG (+)")
        ax.set_title("preconditioner: " + pk.replace("_", "-"))
        if pk == "none":
            ax.legend(fontsize=6, loc="upper left", bbox_to_anchor=(1.02, 1.0))
        ticks = sorted({x_of(r) for r in gm}) + [bi_at["bicgstab"], bi_at["bicg"]]
        names = {full_at: "full", bi_at["bicgstab"]: "BiCGStab", bi_at["bicg"]: "BiCG"}
        ax.set_xticks(ticks)
        ax.set_xticklabels([names.get(t, str(t)) for t in ticks], rotation=30, fontsize=7)
        ax.minorticks_off()
    axes[0].set_ylabel("iterations (red circle: not converged)")
    rl.save(fig, ctx.image("stability_e_krylov"))
    lines = [
        "GMRES(m) over restart lengths m = %s and full GMRES, BiCGStab and BiCG, on the Kelvin box with displacement prescribed "
        "everywhere for n = %s and ν = %s, with block-Jacobi and without a preconditioner (tolerance 1e-10, 1000 iterations)."
        % (", ".join(str(m) for m in sorted({r["restart"] for r in gm if r["restart"] > 0})),
           ", ".join(str(n) for n in sorted({r["n"] for r in rows})),
           ", ".join("%g" % v for v in sorted({r["poisson_ratio"] for r in rows}))), "",
        "![iterations against GMRES restart length](images/stability_e_krylov.png)", "",
        "**Threshold.** " + s["threshold_text"], "", "**Behaviour.** " + s["behaviour"], "",
        "Solves that did not converge, as LinearSolveResult reports them:", "",
        "| n | ν | preconditioner | method | m | status | quantity | iterations | residual |", "|---|---|---|---|---|---|---|---|---|",
    ]
    for r in rows:
        if r["status"] != "converged":
            q = (r["breakdown"] or "").strip('"') or "—"
            lines.append("| %d | %g | %s | %s | %s | %s | %s | %d | %.3g |" % (r["n"], r["poisson_ratio"], r["preconditioner"], r["method"],
                                                                         r["restart"] or "full", r["status"], q, r["iterations"],
                                                                         r["relative_residual"]))
    return "\n".join(lines)
