"""What the report's two finite-element peers share (issue 38; parts/peer.py, parts/peer_liver.py):
the ladder of CalculiX levels on one labelled surface (cached), the reference's own error by
Richardson extrapolation from its last three levels, and the "who wins where" table.
"""

import hashlib
import inspect
import json
import math
from pathlib import Path

import numpy as np

import calculix_peer as fe
import report_lib as rl

FE_COLUMNS = ["level", "h_m", "h_edge_m", "h_asked_m", "nodes", "elements", "equations", "mesh_s", "mesh_peak_rss_bytes", "ccx_s",
              "ccx_peak_rss_bytes", "total_s", "peak_rss_bytes", "volume_m3", "weight_n", "held_area_m2", "tool_area_m2",
              "reaction_n", "patch_node_load_n", "reaction_over_weight", "tool_force_n", "difference_to_next",
              "error_vs_finest"]


def ccx_version():
    ccx = Path("/usr/bin/ccx")
    return rl.file_digest(ccx) if ccx.exists() else "none"  # a new ccx build: a new reference


def fe_code_digest():
    """What a cached CalculiX result depends on: calculix_peer.py and the two functions here that
    run it (not this file's report text, whose edits would otherwise recompute the references)."""
    h = hashlib.sha256(Path(fe.__file__).read_bytes())
    for f in (run_level, fe_ladder):
        h.update(inspect.getsource(f).encode())
    return h.hexdigest()[:16]


def size_text(r):
    """A level's size in mm, with the size asked for where Gmsh meshed another (calculix_peer.SIZE_RETRIES)."""
    asked = r.get("h_asked_m")
    moved = asked and abs(r["h_m"] / asked - 1.0) > 1e-9
    return f"{1e3 * r['h_m']:.3g}" + (f" (asked {1e3 * asked:.3g})" if moved else "")


def pct(x):
    return "–" if x is None else f"{100 * x:.2f} %"


def run_level(ctx, part, surface, lev, h, h_edge, material, tool_displacement=(0.0, 0.0, 0.0), clamp_within=None):
    """One CalculiX level in folder lev: Gmsh then ccx, each a process of its own, timed and with its
    peak memory. Returns the level's row (without the comparisons) and its surface displacements."""
    args = ["/usr/bin/python3", fe.__file__, "mesh", "--surface", surface, "--out", lev, "--h", h, "--h-edge", h_edge,
            "--tool-displacement", ",".join(repr(float(d)) for d in tool_displacement)]
    args += [a for n, v in material.items() for a in (f"--{n}", v)]
    if clamp_within is not None:
        args += ["--clamp-within", clamp_within]
    out, mesh_s, _ = ctx.run_isolated(args, part, timeout=900)
    info = json.loads(out.strip().splitlines()[-1])
    # Peak memory as the programs measure it: run_isolated's ru_maxrss starts from this driver's own.
    out, _, _ = ctx.run_isolated(["/usr/bin/python3", fe.__file__, "ccx", "--dir", lev], part, timeout=1800)
    ccx = json.loads(out.strip().splitlines()[-1])
    u, reactions, volume = fe.read_result(lev)
    np.savez_compressed(Path(lev) / "u.npz", u=u)
    for junk in ("job.inp", "job.frd", "job.dat", "spooles.out"):
        (Path(lev) / junk).unlink(missing_ok=True)
    weight = material["density"] * material["gravity"] * volume
    fix = reactions["FIX"]
    tool = reactions.get("TOOL")
    # ccx's RF is the internal force at the constrained nodes: the gravity load that lands on those
    # nodes themselves is added, so that the sets' forces balance the weight.
    # The sizes meshed (calculix_peer.SIZE_RETRIES: 1-2 % off the sizes asked for where Gmsh failed on those).
    row = {"h_m": info["h"], "h_edge_m": info["h_edge"], "h_asked_m": h, "nodes": info["nodes"], "elements": info["elements"],
           "equations": 3 * info["nodes"], "mesh_s": mesh_s, "mesh_peak_rss_bytes": info["peak_rss_bytes"],
           "ccx_s": ccx["ccx_s"], "ccx_peak_rss_bytes": ccx["peak_rss_bytes"], "total_s": mesh_s + ccx["ccx_s"],
           "peak_rss_bytes": max(info["peak_rss_bytes"], ccx["peak_rss_bytes"]), "volume_m3": volume, "weight_n": weight,
           "held_area_m2": info["held_area_m2"], "tool_area_m2": info["tool_area_m2"],
           "reaction_n": float(fix[2]), "patch_node_load_n": info["patch_node_load_n"],
           "reaction_over_weight": (float(fix[2]) + info["patch_node_load_n"]
                                    + (float(tool[2]) + info["tool_node_load_n"] if tool is not None else 0.0)) / weight,
           "tool_force_n": None if tool is None else float(tool[2]) + info["tool_node_load_n"]}
    return row, u


def fe_ladder(ctx, part, surface, sizes, edge_factor, material, points, weights, tool_displacement=(0.0, 0.0, 0.0),
              agreement=0.01, min_levels=3):
    """The CalculiX levels on `surface` (cached): refined by the sizes given until two consecutive
    levels agree within `agreement` (relative L2 of the surface displacement at `points`), but at
    least `min_levels` (Richardson needs three). Returns the rows, the finest level's folder and
    displacements."""
    key = {"surface": rl.file_digest(surface), "script": fe_code_digest(), "material": material,
           "sizes": sizes, "edge_factor": edge_factor, "agreement": agreement, "min_levels": min_levels,
           "tool": list(tool_displacement), "ccx": ccx_version()}
    d, done = ctx.cache(part + "-calculix", key)
    if done:
        rows = json.loads((d / "levels.json").read_text())
        finest = d / f"level{rows[-1]['level']}"
        return rows, finest, np.load(finest / "u.npz")["u"]
    rows, evals, last_u = [], [], None
    for k, h in enumerate(sizes):
        lev = d / f"level{k}"
        row, u = run_level(ctx, part, surface, lev, h, h / edge_factor, material, tool_displacement)
        rows.append(dict(level=k, **row))
        evals.append(fe.evaluate(lev, u, points))
        last_u = u
        if k > 0:
            rows[-2]["difference_to_next"] = fe.relative_l2(evals[-2], evals[-1], weights)
            rl.warn(f"{part}: FE level {k - 1} -> {k}: {rows[-2]['difference_to_next']:.2%} apart")
            if rows[-2]["difference_to_next"] <= agreement and k + 1 >= min_levels:
                break
    for r, e in zip(rows, evals):
        r["error_vs_finest"] = fe.relative_l2(e, evals[-1], weights) if r is not rows[-1] else None
    (d / "levels.json").write_text(json.dumps(rows, indent=1))
    ctx.mark_cached(d)
    return rows, d / f"level{rows[-1]['level']}", last_u


def richardson(rows):
    """The finest level's own error, from the last three levels (sizes h1 > h2 > h3, a constant ratio
    r assumed): with the differences d12 = |u1 - u2| and d23 = |u2 - u3| (relative L2), the observed
    order p = log(d12 / d23) / log r and the error of level 3 about d23 / (r^p - 1) (the geometric
    tail of the differences still to come). None with fewer than three levels or differences that do
    not shrink (no asymptotic range: the reference's error is then unknown, said so)."""
    if len(rows) < 3:
        return None
    a, b, c = rows[-3], rows[-2], rows[-1]
    d12, d23 = a.get("difference_to_next"), b.get("difference_to_next")
    if not d12 or not d23 or d23 >= d12:
        return None
    r = math.sqrt(b["h_m"] / c["h_m"] * a["h_m"] / b["h_m"])  # the mean ratio of the two steps
    p = math.log(d12 / d23) / math.log(r)
    return {"order": p, "error": d23 / (r ** p - 1.0), "ratio": r}


def richardson_value(rows, key):
    """The extrapolated value of a scalar (the tool's force) from the last three levels and its
    distance from the finest level's; None where the three do not converge monotonically."""
    if len(rows) < 3 or any(r.get(key) is None for r in rows[-3:]):
        return None
    f1, f2, f3 = (r[key] for r in rows[-3:])
    if (f2 - f1) == 0 or (f3 - f2) / (f2 - f1) <= 0 or abs(f3 - f2) >= abs(f2 - f1):
        return None
    q = (f3 - f2) / (f2 - f1)  # = r^-p
    extrapolated = f3 + (f3 - f2) * q / (1.0 - q)
    return {"value": extrapolated, "error": abs(extrapolated - f3) / abs(extrapolated)}


def draw_band(ax, band, label="the reference's own error (Richardson)"):
    """The reference's error as a shaded band from the bottom of the axes up to it: errors inside it
    are not resolved by the reference."""
    if band and band > 0:
        ax.axhspan(ax.get_ylim()[0] if ax.get_ylim()[0] > 0 else band / 100, band, color="tab:gray", alpha=0.18, label=label,
                   zorder=0)
        ax.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0), borderaxespad=0.0)


def who_wins(organ, bem, fem, band, thresholds=(0.05, 0.02, 0.01)):
    """Markdown (issue 38 item 6): for each threshold, the cheapest bemsurg configuration (by wall
    time of the whole process) and the cheapest CalculiX level reaching it, side by side in time
    and memory, and a generated sentence saying which to use. bem rows: label, error_u, wall_s,
    peak_rss_bytes; fem rows: error_vs_finest, total_s, peak_rss_bytes (the finest level has no
    error of its own and is left out)."""
    lines = [f"| {organ}: error ≤ | bemsurg: cheapest configuration | time | peak memory | CalculiX: cheapest level | time "
             "| peak memory | faster |", "|---|---|---|---|---|---|---|---|"]
    verdicts = []
    for t in thresholds:
        b_ok = [r for r in bem if r.get("error_u") is not None and r["error_u"] <= t]
        f_ok = [r for r in fem if r.get("error_vs_finest") is not None and r["error_vs_finest"] <= t]
        b = min(b_ok, key=lambda r: r["wall_s"]) if b_ok else None
        f = min(f_ok, key=lambda r: r["total_s"]) if f_ok else None
        unresolved = band is not None and t < band
        bcell = (f"{b['label']} ({b['error_u']:.2%})", rl.seconds_text(b["wall_s"]), rl.bytes_text(b["peak_rss_bytes"])) \
            if b else ("not reached", "–", "–")
        fcell = (f"h = {1e3 * f['h_m']:.3g} mm, {f['nodes']} nodes ({f['error_vs_finest']:.2%})", rl.seconds_text(f["total_s"]),
                 rl.bytes_text(f["peak_rss_bytes"])) if f else ("not reached below the finest level", "–", "–")
        if b and f:
            ratio = f["total_s"] / b["wall_s"]
            faster = f"bemsurg, {ratio:.2g} ×" if ratio >= 1 else f"CalculiX, {1 / ratio:.2g} ×"
        else:
            faster = "bemsurg" if b else "CalculiX" if f else "neither"
        if unresolved:
            faster += " (below the reference's own error: not resolved)"
        lines.append(f"| {t:.0%} | {bcell[0]} | {bcell[1]} | {bcell[2]} | {fcell[0]} | {fcell[1]} | {fcell[2]} | {faster} |")
        verdicts.append((t, b, f))
    return "\n".join(lines), verdicts


def verdict_text(organ, verdicts, bem, band):
    """The sentence of item 6: which to use when, and where bemsurg loses, by how much."""
    out = []
    wins = [f"{t:.0%}" for t, b, f in verdicts if b and (not f or f["total_s"] >= b["wall_s"])]
    loses = [(t, b, f) for t, b, f in verdicts if f and (not b or f["total_s"] < b["wall_s"])]
    if wins:
        out.append(f"On the {organ}, bemsurg is the quicker way to {', '.join(wins)}: use it for a surface answer at that "
                   "accuracy, and always where the same factorisation then serves many loads (tables, contact, cuts), "
                   "which CalculiX would solve afresh.")
    unreached = [f"{t:.0%}" for t, b, f in verdicts if not b]
    for t, b, f in loses:
        if b:
            why = ("bemsurg's hierarchical solve still couples every element with every other (compressed blocks, "
                   "a serial H-LU), where the sparse finite-element solve couples neighbours only"
                   if b.get("backend") == "hmatrix" else
                   "bemsurg's dense solve grows as n³ while the sparse finite-element solve grows far slower")
            out.append(f"At {t:.0%} CalculiX is {b['wall_s'] / f['total_s']:.2g} × quicker ({rl.seconds_text(f['total_s'])} "
                       f"against {rl.seconds_text(b['wall_s'])}): {why}.")
    if unreached:
        best = min(bem, key=lambda r: r["error_u"])
        out.append(f"None of bemsurg's configurations measured reaches {', '.join(unreached)} (its best: {best['label']}, "
                   f"{best['error_u']:.2%}, {rl.bytes_text(best['peak_rss_bytes'])}): finer meshes than these are needed"
                   + (", which the hierarchical backend reaches at a memory that grows far slower than dense storage's n²."
                      if any(r.get("backend") == "hmatrix" for r in bem) else
                      ", and dense storage grows as n² (the hierarchical backend is the way to them)."))
    if band is not None:
        out.append(f"The reference's own error is about {band:.2%} (Richardson from its last three levels): "
                   "thresholds below it cannot be judged.")
    return " ".join(out)
