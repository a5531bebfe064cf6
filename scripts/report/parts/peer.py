"""A finite-element peer on a shape with no closed form (issues 24 and 38; docs/benchmarks.md).

The body: bemsurg's procedural brain (mesh/brain_model.hpp) upside down, glued to a ceiling by its
flat face (about 139 x 113 mm) and hanging under its own weight. The reference: CalculiX on
quadratic tetrahedra (C3D10) that Gmsh meshes from ONE fine surface of the same body (the brain at
icosphere subdivision 5), the flat face handed to Gmsh as a surface of its own so
that every level clamps exactly it; levels are refined uniformly and, twelve times finer (three in
quick mode), near the face's rim until two consecutive levels agree within 1 % (relative L2 of the surface displacement
at the fine surface's triangle centroids), four levels at least (two in quick mode), and the last
three give the reference's own error (Richardson). bemsurg, on the same fine surface remeshed by
Gmsh with uniform edges h, the flat face kept up to its rim (graded.md, "What a remesh keeps"), clamps the elements on the face
and is compared with the finest level at its own element centroids. Both sides hold the same
area (the part fails past 1 %) and hang the same weight: bemsurg's density is scaled by the
reference's volume over its mesh's (the part fails past 0.5 %). The control: both sides clamped
where bemsurg's remeshes clamped before issue 38 (the face's rim rounded off). The hierarchical
front (issue 40): bemsurg on the hierarchical backend (`bench_organ_gravity --hmatrix 1e-4`) at
meshes finer than the dense sizes.
"""

import json
import sys
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent))
import calculix_peer as fe  # noqa: E402
import peer_support as ps  # noqa: E402
import report_lib as rl  # noqa: E402

NAME = "peer"
TITLE = "A finite-element peer: CalculiX on an organ"
ORDER = 20
# Its data also come from the CalculiX driver and the code both peers share (make_report.py, DATA_SOURCES).
SOURCES = ("scripts/report/calculix_peer.py", "scripts/report/peer_support.py")

MATERIAL = {"young": 3000.0, "poisson": 0.45, "density": 1000.0, "gravity": 9.81}  # bench_organ_gravity's
# The geometry every FE level and every bemsurg mesh shares: 20480 triangles, ~2.3 mm. Not coarser in
# quick mode: at 5120 triangles a 14 mm remesh held 1.51 % more of the face than the reference (the
# part fails past 1 %), and the liver's footprint came out 1.26 % small.
SURFACE_SUBDIVISIONS = 5
# The size on the face's rim is h / EDGE_FACTOR (the clamped edge's stress singularity). Three
# times finer left the levels' convergence to the rim: on issue 38's hung liver they came 1.93,
# 0.90, 0.58 and 0.29 % apart from 12 to 3.5 mm, an order drifting from 1.4 to 0.5; twelve times
# finer, 0.41 and 0.18 % apart from 8.5 to 4.25 mm, order 2.4, 0.14 % own error (docs/benchmarks.md).
# Quick mode (CI) keeps three: its two coarse levels only check the pipeline, and twelve made this
# part 67 s instead of 19 s.
EDGE_FACTOR = {"quick": 3.0, "full": 12.0}
AGREEMENT = 0.01  # two consecutive FE levels within 1 %: the finer is the reference
FE_SIZES = {"quick": [0.016, 0.012], "full": [0.012, 0.0085, 0.006, 0.00425]}  # m, a factor sqrt(2) apart
# m: bemsurg's meshes, the same fine surface remeshed by Gmsh with uniform edges (the face kept);
# 6 mm gives about 3700 elements, 11000 dense equations.
# 16 mm is left out: its remesh held 1.41 % less of the face than the reference (rim loss asked: 0.2 %),
# past the 1 % the comparison allows; 12 mm held 0.66 % more, 8.5 mm 0.41 % more, 6 mm 0.14 % less.
BEM_SIZES = {"quick": [0.02, 0.014], "full": [0.012, 0.0085, 0.006]}
# The hierarchical front: finer than dense LU goes here (4.25 mm: about 7,400 elements; 3 mm: about 15,000).
HMATRIX_SIZES = {"quick": [0.02], "full": [0.00425, 0.003]}
HMATRIX_TOLERANCE = 1e-4
RIM_AREA_LOSS = 0.002  # the remesh meshes the face's rim so that its chords lose about this much of it
CONTROL_SIZES = {"quick": [0.02], "full": [0.016, 0.0085]}  # the old clamp, at two of bemsurg's sizes
CONTROL_LEVEL = {"quick": 1, "full": 2}  # the FE level the old clamp is tried on
AREA_AGREEMENT, WEIGHT_AGREEMENT = 0.01, 0.005  # issue 38 item 5: past these the comparison is unfair, the part fails

FE_COLUMNS = ps.FE_COLUMNS
BEM_COLUMNS = ["edge_length_m", "elements", "equations", "clamped_elements", "assembly_s", "solve_s", "total_s", "wall_s",
               "peak_rss_bytes", "weight_n", "clamped_area_m2", "face_area_m2", "reaction_over_weight", "max_displacement_m",
               "error_u", "reference_level", "backend"]
CONTROL_COLUMNS = ["edge_length_m", "elements", "clamped_area_m2", "face_area_m2", "bem_error_u", "bem_error_u_face_kept",
                   "fe_level", "fe_held_area_m2", "fe_change"]


def _bem(ctx, bench, pd, tag, h, hung_volume, extra):
    """One bemsurg size (a process of its own): its JSON, its points and its wall time and memory."""
    js, pts = pd / f"bem_{tag}.json", pd / f"bem_{tag}_points.csv"
    _, wall, _ = ctx.run_isolated([bench, "--edge-length", h, "--surface-subdivisions", SURFACE_SUBDIVISIONS,
                                   "--hung-volume", hung_volume, "--points-out", pts, "--json", js] + extra, NAME, timeout=900)
    p = np.loadtxt(rl.data_path(pts), delimiter=",", skiprows=1)
    pts.unlink()
    return json.loads(js.read_text()), p, wall


def run(ctx):
    pd = ctx.part_dir(NAME)
    bench = ctx.program("bench_organ_gravity")
    surface = pd / "surface.obj"
    ctx.run([bench, "--write-surface", surface, "--surface-subdivisions", SURFACE_SUBDIVISIONS], NAME)
    points, weights, _ = fe.surface_points(surface)
    fe_rows, finest, u_ref = ps.fe_ladder(ctx, NAME, surface, FE_SIZES[ctx.mode], EDGE_FACTOR[ctx.mode], MATERIAL, points, weights,
                                          agreement=AGREEMENT, min_levels=4 if ctx.mode == "full" else 2)
    rl.write_csv(pd / "fem_levels.csv", fe_rows, FE_COLUMNS)
    ref = fe_rows[-1]
    face_area = ref["held_area_m2"]  # what the reference clamps
    bem_rows = []
    runs = [(f"{k}", h, []) for k, h in enumerate(BEM_SIZES[ctx.mode])]
    runs += [(f"h{k}", h, ["--hmatrix", HMATRIX_TOLERANCE]) for k, h in enumerate(HMATRIX_SIZES[ctx.mode])]
    for tag, h, backend in runs:
        try:
            j, p, wall = _bem(ctx, bench, pd, tag, h, ref["volume_m3"], ["--rim-area-loss", RIM_AREA_LOSS] + backend)
        except rl.PartFailed as e:  # a build without hmat-oss: the hierarchical front is left out, and said
            if not backend or "without hmat-oss" not in str(e):
                raise
            rl.warn(f"peer: the hierarchical front at h = {h} m left out: {str(e).splitlines()[-1]}")
            continue
        u_fe = fe.evaluate(finest, u_ref, p[:, :3])
        bem_rows.append({"edge_length_m": h, "elements": j["elements"], "equations": j["equations"],
                         "clamped_elements": j["clamped_elements"], "assembly_s": j["assembly_s"], "solve_s": j["solve_s"],
                         "total_s": j["total_s"], "wall_s": wall, "peak_rss_bytes": j["peak_rss_bytes"], "weight_n": j["weight_n"],
                         "clamped_area_m2": j["patch_area_m2"], "face_area_m2": face_area,
                         "reaction_over_weight": j["reaction_over_weight"], "max_displacement_m": j["max_displacement_m"],
                         "error_u": fe.relative_l2(p[:, 5:8], u_fe, p[:, 3]), "reference_level": ref["level"],
                         "backend": j.get("backend", "dense")})
        for what, mine, theirs, limit in (("held area", j["patch_area_m2"], face_area, AREA_AGREEMENT),
                                          ("weight", j["weight_n"], ref["weight_n"], WEIGHT_AGREEMENT)):
            if abs(mine / theirs - 1.0) > limit:
                raise rl.PartFailed(f"peer: at h = {h} m bemsurg's {what} is {mine:.6g}, the reference's {theirs:.6g}: "
                                    f"{abs(mine / theirs - 1):.2%} apart (limit {limit:.1%}); the comparison would be unfair")
    rl.write_csv(pd / "bem_levels.csv", bem_rows, BEM_COLUMNS)
    rl.write_csv(pd / "old_clamp.csv", _control(ctx, bench, pd, surface, fe_rows, finest, u_ref, bem_rows, points, weights),
                 CONTROL_COLUMNS)


def _control(ctx, bench, pd, surface, fe_rows, finest, u_ref, bem_rows, points, weights):
    """Issue 38 item 5's control: bemsurg remeshed without keeping the face (as before the issue), and
    the finite-element model clamped on the same triangles, against its own level clamped on the
    whole face: what the support alone did to both."""
    level = min(CONTROL_LEVEL[ctx.mode], len(fe_rows) - 1)
    base = fe_rows[level]
    base_dir = finest.parent / f"level{level}"
    base_eval = fe.evaluate(base_dir, np.load(base_dir / "u.npz")["u"], points)
    rows = []
    for k, h in enumerate(CONTROL_SIZES[ctx.mode]):
        tris = pd / f"old_clamp_{k}.csv"
        j, p, _ = _bem(ctx, bench, pd, f"old_{k}", h, fe_rows[-1]["volume_m3"], ["--old-clamp", "--clamped-out", tris])
        err = fe.relative_l2(p[:, 5:8], fe.evaluate(finest, u_ref, p[:, :3]), p[:, 3])
        key = {"surface": rl.file_digest(surface, tris), "script": ps.fe_code_digest(), "h": base["h_m"],
               "material": MATERIAL, "ccx": ps.ccx_version()}
        d, done = ctx.cache(NAME + "-old-clamp", key)
        lev = d / "level"
        if not done:
            row, u = ps.run_level(ctx, NAME, surface, lev, base["h_m"], base["h_edge_m"], MATERIAL, clamp_within=tris)
            (d / "row.json").write_text(json.dumps(row))
            ctx.mark_cached(d)
        row = json.loads((d / "row.json").read_text())
        change = fe.relative_l2(fe.evaluate(lev, np.load(lev / "u.npz")["u"], points), base_eval, weights)
        kept = next((r["error_u"] for r in bem_rows if r["edge_length_m"] == h and r.get("backend") != "hmatrix"), None)
        rows.append({"edge_length_m": h, "elements": j["elements"], "clamped_area_m2": j["patch_area_m2"],
                     "face_area_m2": fe_rows[-1]["held_area_m2"], "bem_error_u": err, "bem_error_u_face_kept": kept,
                     "fe_level": level, "fe_held_area_m2": _held_area(lev), "fe_change": change})
        tris.unlink()
    return rows


def _held_area(lev):
    """The area of the FE surface triangles whose three corners are held (the old clamp's FE area)."""
    d = np.load(lev / "mesh.npz")
    held = np.zeros(len(d["xyz"]), bool)
    held[d["held"]] = True
    t = d["tris"][held[d["tris"][:, :3]].all(axis=1), :3]
    x = d["xyz"]
    return float(0.5 * np.linalg.norm(np.cross(x[t[:, 1]] - x[t[:, 0]], x[t[:, 2]] - x[t[:, 0]]), axis=1).sum())


def render(ctx):
    pd = ctx.out / NAME
    fem = rl.read_csv(pd / "fem_levels.csv")
    bem = rl.read_csv(pd / "bem_levels.csv")
    control = rl.read_csv(pd / "old_clamp.csv")
    ref = fem[-1]
    fe_pts = [r for r in fem if r.get("error_vs_finest")]
    band = ps.richardson(fem)

    fig, (ax1, ax2) = rl.plt.subplots(1, 2, figsize=(11, 4.4), dpi=110)
    for ax in (ax1, ax2):
        ax.grid(True, which="both", alpha=0.3)
    dense = [r for r in bem if r.get("backend") != "hmatrix"]
    hier = [r for r in bem if r.get("backend") == "hmatrix"]
    rl.work_precision(ax1, {"bemsurg (BEM, surface triangles)": [(r["equations"], r["error_u"], r) for r in dense],
                            **({"bemsurg, hierarchical (hmatrix)": [(r["equations"], r["error_u"], r) for r in hier]} if hier else {}),
                            "CalculiX C3D10 vs its finest level": [(r["equations"], r["error_vs_finest"], r) for r in fe_pts]},
                      "unknowns (3 × BEM elements; 3 × FE nodes)", "relative L2 error of surface displacement",
                      annotate=lambda r: f"h={1e3 * r.get('h_m', r.get('edge_length_m')):.3g} mm")
    ax1.set_title("Error against problem size")
    front = rl.work_precision(ax2, {"bemsurg (whole process)": [(r["wall_s"], r["error_u"], r) for r in dense],
                                    **({"bemsurg, hierarchical (whole process)": [(r["wall_s"], r["error_u"], r) for r in hier]}
                                       if hier else {}),
                                    "CalculiX (Gmsh + ccx)": [(r["total_s"], r["error_vs_finest"], r) for r in fe_pts]},
                              "wall time to solution (s)", "relative L2 error of surface displacement")
    ax2.set_title("Work-precision: error against time")
    for ax in (ax1, ax2):
        ps.draw_band(ax, band["error"] if band else None)
    fig.suptitle(f"Hanging brain, reference: CalculiX {ref['elements']} C3D10 ({ref['nodes']} nodes)", fontsize=9)
    rl.save(fig, ctx.image("peer_work_precision"))

    bem_named = [dict(r, label=f"constant{', hierarchical' if r.get('backend') == 'hmatrix' else ''}, "
                                 f"h = {1e3 * r['edge_length_m']:.3g} mm ({r['elements']} el.)") for r in bem]
    table, verdicts = ps.who_wins("brain", bem_named, fe_pts, band["error"] if band else None)
    lines = [" ".join(__doc__.split("\n\n")[1].split()), "",
             f"Material E = {MATERIAL['young']:g} Pa, ν = {MATERIAL['poisson']:g}, ρ = {MATERIAL['density']:g} kg/m³ "
             f"(bemsurg's scaled to the reference's volume), g = {MATERIAL['gravity']:g} m/s²; the whole flat face clamped. "
             "The FE errors are against the finest level (which has none by definition): they show what a coarser "
             "FE mesh would have cost and missed; the grey band is the finest level's own error.", "",
             "![Error of bemsurg and of the CalculiX levels against the finest CalculiX level, by size and by time]"
             "(images/peer_work_precision.png)", "",
             "**The CalculiX levels** (what each finite-element size costs; the reaction on the face against the weight ρ g V "
             "with V the volume ccx integrates; ccx's RF is the internal force at the clamped nodes, so the gravity load "
             "that lands on those nodes themselves is added to it). Times: one run each (a level of CalculiX takes up to minutes "
             "and its answer is cached; not repeated):", "",
             "| level | h (mm) | h at the rim (mm) | nodes | C3D10 | Gmsh (s) | ccx (s) | ccx peak memory | held area (cm²) "
             "| reaction / weight | difference to next level |", "|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in fem:
        lines.append(f"| {r['level']} | {ps.size_text(r)} | {1e3 * r['h_edge_m']:.3g} | {r['nodes']} | {r['elements']} | "
                     f"{rl.seconds_text(r['mesh_s'])} | {rl.seconds_text(r['ccx_s'])} | {rl.bytes_text(r['ccx_peak_rss_bytes'])} | "
                     f"{1e4 * r['held_area_m2']:.2f} | {r['reaction_over_weight']:.4f} | {ps.pct(r.get('difference_to_next'))} |")
    lines += ["", "**bemsurg** (the same fine surface remeshed by Gmsh with edges of about h, the flat face kept with a rim "
              f"area loss of {RIM_AREA_LOSS:.1%}; error against the finest CalculiX level at the element centroids, "
              "area-weighted; the process's time includes the remeshing; times from one run of each size):", "",
              "| h (mm) | backend | elements | equations | assembly (s) | solve (s) | process (s) | peak memory "
              "| held area / reference's | weight / reference's | reaction / weight | error |",
              "|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in bem:
        lines.append(f"| {1e3 * r['edge_length_m']:.3g} | {r.get('backend') or 'dense'} | {r['elements']} | {r['equations']} | "
                     f"{rl.seconds_text(r['assembly_s'])} | "
                     f"{rl.seconds_text(r['solve_s'])} | {rl.seconds_text(r['wall_s'])} | {rl.bytes_text(r['peak_rss_bytes'])} | "
                     f"{r['clamped_area_m2'] / r['face_area_m2']:.4f} | {r['weight_n'] / ref['weight_n']:.4f} | "
                     f"{r['reaction_over_weight']:.4f} | {ps.pct(r['error_u'])} |")
    lines += ["", "**The control: the old clamp.** bemsurg remeshed as before issue 38 (the face's rim rounded off by the "
              "remesh, the elements whose centroid lies on the plane clamped), and the finite-element model at level "
              f"{control[0]['fe_level'] if control else '–'} clamped on the same triangles, against the same level clamped on the "
              "whole face: how much of the error the support alone made.", "",
              "| h (mm) | bemsurg clamps (of the face) | FE clamps (of the face) | FE answer changed by | bemsurg error, old clamp "
              "| bemsurg error, face kept |", "|---|---|---|---|---|---|"]
    for r in control:
        lines.append(f"| {1e3 * r['edge_length_m']:.3g} | {r['clamped_area_m2'] / r['face_area_m2']:.1%} | "
                     f"{r['fe_held_area_m2'] / r['face_area_m2']:.1%} | {ps.pct(r['fe_change'])} | {ps.pct(r['bem_error_u'])} | "
                     f"{ps.pct(r.get('bem_error_u_face_kept'))} |")
    lines += ["", "**Who wins where** (the cheapest configuration of each side reaching each error, whole process, this "
              "machine, this run):", "", table, "", _findings(fem, bem, front, band), "",
              ps.verdict_text("brain", verdicts, bem_named, band["error"] if band else None)]
    return "\n".join(lines)


def _findings(fem, bem, front, band):
    """Generated text: the convergence of the reference, the reaction checks, the comparison by ratios."""
    ref = fem[-1]
    out = []
    diffs = [r.get("difference_to_next") for r in fem if r.get("difference_to_next") is not None]
    if diffs and diffs[-1] <= AGREEMENT:
        out.append(f"The reference converged: its last two levels agree within {ps.pct(diffs[-1])} (goal {AGREEMENT:.0%}).")
    else:
        out.append(f"**The reference did not reach the {AGREEMENT:.0%} agreement** in this run (last two levels "
                   f"{ps.pct(diffs[-1] if diffs else None)} apart; quick mode stops after two coarse levels): the errors below "
                   "are against a reference that is itself this uncertain.")
    if band:
        out.append(f"Richardson from its last three levels: observed order {band['order']:.2g} in h, the finest level's own "
                   f"error about {ps.pct(band['error'])}.")
    else:
        out.append("The reference's own error could not be estimated (fewer than three levels, or differences that do not "
                   "shrink).")
    worst_fe = max(abs(r["reaction_over_weight"] - 1) for r in fem)
    out.append(f"The CalculiX reactions balance the weight within {ps.pct(worst_fe)} at every level"
               + (" (goal 0.5 %)." if worst_fe <= 0.005 else " — **more than the 0.5 % expected**."))
    worst_bem = max(abs(r["reaction_over_weight"] - 1) for r in bem)
    out.append(f"bemsurg's reactions (traction × area summed over the clamped elements) balance its weight within {ps.pct(worst_bem)}.")
    shares = ", ".join(f"{r['clamped_area_m2'] / r['face_area_m2']:.2%}" for r in bem)
    out.append(f"bemsurg clamps {shares} of the area the reference clamps (h = "
               + ", ".join(f"{1e3 * r['edge_length_m']:.3g}" for r in bem) + " mm) and hangs the same weight.")
    best = min(bem, key=lambda r: r["error_u"])
    out.append(f"bemsurg's best error is {ps.pct(best['error_u'])} with {best['elements']} elements ({rl.seconds_text(best['wall_s'])}); "
               f"CalculiX's finest level, the reference, took {rl.seconds_text(ref['total_s'])} (Gmsh + ccx): "
               f"{ref['total_s'] / best['wall_s']:.2g} × that time.")
    winners = sorted({f[2] for f in front})
    out.append("On the time chart the Pareto front holds: " + ", ".join(winners) + ".")
    return " ".join(out)
