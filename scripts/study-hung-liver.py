#!/usr/bin/env python3
"""Issue 38's hung-liver study (docs/graded.md, "Rim refinement"): what `refine_rim` does to the
error of an organ hung from a patch, on both element types, against a converged C3D10 reference.

The organ: `bemsurg sample-segmentation liver` prepared to about 2,336 elements, hung under its own
weight from the elements whose centroids lie within 35 mm of its top vertex (an element list),
E = 5 kPa, nu = 0.45, rho = 1060 kg/m^3. The reference: CalculiX levels on the same faceted surface
(scripts/report/calculix_peer.py) at 8.5, 6 and 4.25 mm, graded to h / 12 on the patch's rim, and
Richardson from the three; the levels are cached in OUT. The error: relative L2 of the surface
displacement at bemsurg's element centroids (constant elements) or edge midpoints (linear
elements), against the extrapolated field; the scale is the best-fit factor of bemsurg's field
against it (above 1: too soft).

usage: study-hung-liver.py --build BUILD --out OUT [--series etype:rim:method ...]
About 25 minutes and 10 GB on a 2-core machine (the finest CalculiX level); writes OUT/results.csv.
"""

import argparse
import csv
import json
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

REPO = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(REPO / "scripts/report"))
import calculix_peer as fe  # noqa: E402
import peer_support as ps  # noqa: E402
import report_lib as rl  # noqa: E402

MATERIAL = {"young": 5000.0, "poisson": 0.45, "density": 1060.0, "gravity": 9.81}
FE_SIZES = [0.0085, 0.006, 0.00425]
EDGE_FACTOR = 12.0
PATCH_RADIUS = 0.035
SERIES = ["constant:0:lu", "constant:1:auto", "constant:2:auto", "linear:2:hmatrix", "linear:3:hmatrix"]


def read_obj(path):
    v, f = [], []
    for line in Path(path).read_text().splitlines():
        if line.startswith("v "):
            v.append([float(x) for x in line.split()[1:4]])
        elif line.startswith("f "):
            f.append([int(x.split("/")[0]) - 1 for x in line.split()[1:4]])
    return np.array(v), np.array(f)


def compared_points(o):
    """Points, weights and bemsurg's displacements there (module docstring)."""
    def rows(p):
        with open(p) as fh:
            return [{k: float(v) for k, v in r.items()} for r in csv.DictReader(fh)]
    if (o / "corners.csv").exists():
        c = rows(o / "corners.csv")
        area = {int(r["element"]): r["area"] for r in rows(o / "elements.csv")}
        x = np.array([[r["x"], r["y"], r["z"]] for r in c]).reshape(-1, 3, 3)
        u = np.array([[r["ux"], r["uy"], r["uz"]] for r in c]).reshape(-1, 3, 3)
        w = np.array([area[int(r["element"])] / 3.0 for r in c[::3]])
        pairs = ((0, 1), (1, 2), (2, 0))
        return (np.concatenate([0.5 * (x[:, a] + x[:, b]) for a, b in pairs]), np.concatenate([w] * 3),
                np.concatenate([0.5 * (u[:, a] + u[:, b]) for a, b in pairs]))
    e = rows(o / "elements.csv")
    return (np.array([[r["cx"], r["cy"], r["cz"]] for r in e]), np.array([r["area"] for r in e]),
            np.array([[r["ux"], r["uy"], r["uz"]] for r in e]))


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--build", type=Path, required=True)
    ap.add_argument("--out", type=Path, required=True)
    ap.add_argument("--series", nargs="*", default=SERIES, help="etype:refine_rim:method (default: %(default)s)")
    a = ap.parse_args()
    out = a.out.resolve()
    out.mkdir(parents=True, exist_ok=True)
    exe = a.build.resolve() / "bin/bemsurg"
    stl, obj = out / "liver.stl", out / "prepared.obj"
    if not obj.exists():
        subprocess.run([str(exe), "sample-segmentation", "liver", "-o", str(stl)], check=True, capture_output=True)
        subprocess.run([str(exe), "prepare", str(stl), "--units", "mm", "--target-elements", "2336", "-o", str(obj)],
                       check=True, capture_output=True)
    v, f = read_obj(obj)
    top = v[np.argmax(v[:, 2])]
    held = np.where(np.linalg.norm(v[f].mean(axis=1) - top, axis=1) <= PATCH_RADIUS)[0]
    surface = out / "surface.obj"  # the FE side's labelled copy: the patch as a surface of its own
    with open(surface, "w") as fh:
        fh.writelines(f"v {float(x)!r} {float(y)!r} {float(z)!r}\n" for x, y, z in v)
        hs = set(held.tolist())
        for name, sel in (("free", [i for i in range(len(f)) if i not in hs]), ("held", sorted(hs))):
            fh.write(f"g {name}\n")
            fh.writelines(f"f {f[i][0] + 1} {f[i][1] + 1} {f[i][2] + 1}\n" for i in sel)
    ctx = rl.Context(out, a.build.resolve(), REPO, False)
    points, weights, _ = fe.surface_points(surface)
    levels, finest, u3 = ps.fe_ladder(ctx, "hung-liver", surface, FE_SIZES, EDGE_FACTOR, MATERIAL, points, weights,
                                      agreement=0.0, min_levels=3)
    band = ps.richardson(levels)
    if band is None:
        sys.exit("study-hung-liver: the CalculiX levels do not converge monotonically: no reference")
    second = finest.parent / f"level{levels[-2]['level']}"
    u2 = np.load(second / "u.npz")["u"]
    tail = 1.0 / (band["ratio"] ** band["order"] - 1.0)
    print(f"reference: levels {[round(1e3 * r['h_m'], 2) for r in levels]} mm, observed order {band['order']:.2f}, "
          f"own error {band['error']:.2%}", flush=True)
    results = []
    for spec in a.series:
        etype, rim, method = spec.split(":")
        rule = {"select": {"elements": held.tolist()}, "displacement": [0, 0, 0]}
        if int(rim):
            rule["refine_rim"] = int(rim)
        solver = {"method": method, **({"compression_tolerance": 1e-4} if method == "hmatrix" else {})}
        scene = {"mesh": {"file": str(obj)}, "elements": etype, "gravity": [0, 0, -MATERIAL["gravity"]],
                 "material": {"young_modulus": MATERIAL["young"], "poisson_ratio": MATERIAL["poisson"],
                              "density": MATERIAL["density"]},
                 "boundary_conditions": {"rules": [rule]}, "solver": solver}
        tag = spec.replace(":", "_")
        (out / f"scene_{tag}.json").write_text(json.dumps(scene))
        o = out / f"out_{tag}"
        start = time.time()
        r = subprocess.run([str(exe), "solve", str(out / f"scene_{tag}.json"), "-o", str(o), "--quiet"],
                           capture_output=True, text=True)
        wall = time.time() - start
        if r.returncode != 0:
            print(f"{spec}: bemsurg solve failed:\n{r.stderr[-2000:]}", flush=True)
            continue
        report = json.loads((o / "report.json").read_text())
        p, w, u = compared_points(o)
        e3, e2 = fe.evaluate(finest, u3, p), fe.evaluate(second, u2, p)
        ref = e3 + (e3 - e2) * tail
        scale = float(np.sum(w[:, None] * u * ref) / np.sum(w[:, None] * ref * ref))
        row = {"series": spec, "elements": report["elements"], "backend": report.get("backend", {}).get("name", "dense"),
               "wall_s": round(wall, 2), "peak_memory_mb": report.get("peak_memory_mb"),
               "error": fe.relative_l2(u, ref, w), "error_vs_finest_level": fe.relative_l2(u, e3, w), "scale": scale,
               "reference_own_error": band["error"]}
        results.append(row)
        print(json.dumps(row), flush=True)
        with open(out / "results.csv", "w", newline="") as fh:
            writer = csv.DictWriter(fh, fieldnames=list(row))
            writer.writeheader()
            writer.writerows(results)


if __name__ == "__main__":
    main()
