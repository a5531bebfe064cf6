"""Stability study (a): Poisson's ratio towards 0.5 (issue 25, docs/stability.md). bench_stability
--study poisson solves three closed-form problems (Kelvin box with displacement everywhere, the
same box mixed, Lamé's hollow sphere with its cavity displaced) for nu up to 0.5 - 1e-8 with LU,
GMRES, BiCGStab and BiCG (block-Jacobi), and writes stability_a_poisson.csv: problem,
poisson_ratio, gap (0.5 - nu), elements, condition (2-norm of A* by SVD), method, status,
iterations, relative_residual, error (relative L2 against the closed form; empty: refused).
"""

import report_lib as rl

NAME = "stability_a"
TITLE = "(a) Poisson's ratio towards 0.5"
ORDER = 101
STUDY = "poisson"
PROBLEM_TEXT = {"kelvin_dirichlet": "Kelvin box, displacement everywhere", "kelvin_mixed": "Kelvin box, mixed",
                "lame_mixed": "Lamé sphere, cavity displaced"}
METHOD_TEXT = {"lu": "LU", "gmres": "GMRES", "bicgstab": "BiCGStab", "bicg": "BiCG"}


def run(ctx):
    rl.run_stability_study(ctx, NAME, STUDY)


def _past_100(rows, problem, method):
    """The ν from which the error stays above 100 % up to the last ν swept (None: never), over the
    solves that gave an error (a refused or failed solve is not measured)."""
    pts = sorted((r["poisson_ratio"], r["error"]) for r in rows
                 if r["problem"] == problem and r["method"] == method and r["error"] is not None)
    first = None
    for nu, err in pts:
        if err > 1.0:
            first = nu if first is None else first
        else:
            first = None
    return first


def _threshold_text(rows):
    """What the table below shows, problem by problem and solver by solver (issue 37: the text
    once said "every solver" where the table disagreed)."""
    held = [p for p in PROBLEM_TEXT if p != "kelvin_mixed" and any(r["problem"] == p for r in rows)]
    parts, lu_firsts = [], []
    for p in held:
        firsts = {m: _past_100(rows, p, m) for m in METHOD_TEXT}
        lu_firsts.append((firsts["lu"], p))
        def at(v):
            return "never (up to the last ν swept)" if v is None else f"from ν = {v:.10g}"
        if len(set(firsts.values())) == 1:
            parts.append(f"{PROBLEM_TEXT[p]}: {at(firsts['lu'])} for every solver")
        else:
            parts.append(f"{PROBLEM_TEXT[p]}: " + ", ".join(f"{METHOD_TEXT[m]} {at(v)}" for m, v in firsts.items()))
    mixed = [r["error"] for r in rows if r["problem"] == "kelvin_mixed" and r["method"] == "lu" and r["error"] is not None]
    known = [(v, p) for v, p in lu_firsts if v is not None]
    wrong = [r for r in rows if r["problem"] in held and r["method"] != "lu" and r["error"] is not None and r["error"] > 1.0]
    claimed = sum(1 for r in wrong if r["status"] == "converged")
    text = ("With a closed surface component whose displacement is prescribed everywhere, cond(A*) grows as 1/(0.5 − ν) "
            "and the error against the closed form passes 100 % and stays there — " + "; ".join(parts) + ". "
            f"Of the {len(wrong)} Krylov solves more than 100 % off, {claimed} reported convergence.")
    if known:
        v, p = min(known)
        text += f" The earliest, ν = {v:.10g} ({PROBLEM_TEXT[p]}, LU), is what the refusal must precede."
    if mixed:
        text += f" The mixed Kelvin problem stays below {100 * max(mixed):.1f} % up to the last ν swept."
    return text


def render(ctx):
    s = rl.read_stability_summary(ctx, NAME, STUDY)
    rows = rl.read_csv(ctx.part_dir(NAME) / "stability_a_poisson.csv")
    fig, (ax, ax2) = rl.plt.subplots(1, 2, figsize=(11, 4.4), dpi=110)
    for a in (ax, ax2):
        a.grid(True, which="both", alpha=0.3)
    problems = list(dict.fromkeys(r["problem"] for r in rows))
    for i, p in enumerate(problems):
        for j, m in enumerate(METHOD_TEXT):
            pts = [(r["gap"], r["error"]) for r in rows if r["problem"] == p and r["method"] == m and r["error"] is not None]
            if pts:
                ax.plot(*zip(*pts), marker=rl.MARKERS[j], color=f"C{i}", alpha=0.8, ms=4 + 2 * (3 - j),
                        fillstyle="none", label=f"{PROBLEM_TEXT.get(p, p)}, {METHOD_TEXT[m]}")
        cond = [(r["gap"], r["condition"]) for r in rows if r["problem"] == p and r["method"] == "lu"]
        ax2.plot(*zip(*cond), marker="o", color=f"C{i}", label=PROBLEM_TEXT.get(p, p))
    for a in (ax, ax2):
        a.set_xscale("log")
        a.set_yscale("log")
        a.set_xlabel("0.5 - ν")
        a.invert_xaxis()
        a.axvline(0.5 - s["warning_poisson_ratio"], color="orange", ls="--", label="warning (ν = %g)" % s["warning_poisson_ratio"])
        a.axvline(0.5 - s["limit_poisson_ratio"], color="red", ls="--", label="refused (ν = %g)" % s["limit_poisson_ratio"])
    ax.set_ylabel("relative error against the closed form")
    ax.legend(fontsize=6, ncol=2)
    ax2.set_ylabel("cond₂(A*) (SVD)")
    ax2.legend(fontsize=7)
    rl.save(fig, ctx.image("stability_a_poisson"))
    lines = [
        "Poisson's ratio swept from %.10g to %.10g on three closed-form problems, each solved by LU, GMRES, BiCGStab and BiCG "
        "(block-Jacobi preconditioner, tolerance 1e-10); the condition number is the 2-norm of A* by SVD. The study assembles "
        "A* itself and calls solve_linear_system, below solve_elastostatic's check, so it sweeps past the ν that bemsurg refuses."
        % (min(r["poisson_ratio"] for r in rows), max(r["poisson_ratio"] for r in rows)), "",
        "![error and condition number against 0.5 - nu](images/stability_a_poisson.png)", "",
        "**Threshold.** " + _threshold_text(rows), "", "**Behaviour.** " + s["behaviour"], "",
        "| problem | ν | elements | cond₂(A*) | LU error | Krylov iterations (GMRES / BiCGStab / BiCG) | Krylov status |",
        "|---|---|---|---|---|---|---|",
    ]
    for p in problems:
        for nu in sorted({r["poisson_ratio"] for r in rows if r["problem"] == p}):
            g = {r["method"]: r for r in rows if r["problem"] == p and r["poisson_ratio"] == nu}
            err = g["lu"]["error"]
            its = " / ".join(str(g[m]["iterations"]) for m in ("gmres", "bicgstab", "bicg"))
            st = ", ".join(sorted({g[m]["status"] for m in ("gmres", "bicgstab", "bicg")}))
            lines.append("| %s | %.10g | %d | %.3g | %s | %s | %s |" % (PROBLEM_TEXT.get(p, p), nu, g["lu"]["elements"], g["lu"]["condition"],
                                                                   "—" if err is None else "%.3g" % err, its, st))
    return "\n".join(lines)
