#!/usr/bin/env python3
"""Renders docs/images/organ-prepare.png for docs/organs.md (run by scripts/make-organ-pictures.sh).

Three panels, one camera: the raw liver segmentation as `bemsurg sample-segmentation` writes it
(every triangle drawn, its defects found here from the triangles alone and marked), the mesh
`bemsurg prepare` makes of it (default target, element edges drawn) and the mesh the organ scene
solves (graded to its operating region; the held and operating spheres coloured).

usage: organ-pictures.py RAW.stl PREPARED.obj SOLVED.obj SCENE.json OUT.png
"""
import io
import json
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from mpl_toolkits.mplot3d.art3d import Poly3DCollection  # noqa: E402
from PIL import Image  # noqa: E402

ELEV, AZIM = 28.0, -62.0  # looking at the anterior surface (-y) of the right lobe (+x), from above
LIGHT = np.array([-0.4, -1.0, 1.2]) / np.linalg.norm([-0.4, -1.0, 1.2])


def read_stl(path):
    """Binary STL: (vertices welded by exact coordinates, faces)."""
    data = open(path, "rb").read()
    n = int(np.frombuffer(data, "<u4", 1, 80)[0])
    rec = np.frombuffer(data, np.dtype([("n", "<f4", 3), ("v", "<f4", (3, 3)), ("a", "<u2")]), n, 84)
    corners = rec["v"].reshape(-1, 3).astype(float)
    vertices, index = np.unique(corners, axis=0, return_inverse=True)
    return vertices, index.reshape(-1, 3)


def read_obj(path):
    v, f = [], []
    for line in open(path):
        if line.startswith("v "):
            v.append([float(x) for x in line.split()[1:4]])
        elif line.startswith("f "):
            f.append([int(x.split("/")[0]) - 1 for x in line.split()[1:4]])
    return np.array(v), np.array(f)


def find_defects(v, f):
    """Face masks of each defect kind, found from the welded triangles (as docs/organs.md names them)."""
    a, b, c = v[f[:, 0]], v[f[:, 1]], v[f[:, 2]]
    area = 0.5 * np.linalg.norm(np.cross(b - a, c - a), axis=1)
    edges = np.stack([f[:, [0, 1]], f[:, [1, 2]], f[:, [2, 0]]], axis=1).reshape(-1, 2)
    face_of = np.repeat(np.arange(len(f)), 3)
    key = np.sort(edges, axis=1)
    _, inv, count = np.unique(key, axis=0, return_inverse=True, return_counts=True)
    per_edge = count[inv]
    # The same directed edge used twice: two neighbours that disagree on orientation.
    _, dinv, dcount = np.unique(edges, axis=0, return_inverse=True, return_counts=True)
    flipped_edge = (dcount[dinv] > 1) & (per_edge == 2)
    masks = {}
    masks["zero-area faces"] = area < 1e-12 * area.max()
    masks["fin (non-manifold edge)"] = np.zeros(len(f), bool)
    masks["fin (non-manifold edge)"][face_of[per_edge > 2]] = True
    boundary = np.zeros(len(f), bool)
    boundary[face_of[per_edge == 1]] = True
    masks["hole rim"] = boundary & ~masks["fin (non-manifold edge)"]
    masks["flipped patch (rim)"] = np.zeros(len(f), bool)
    masks["flipped patch (rim)"][face_of[flipped_edge]] = True
    longest = np.max(np.linalg.norm(np.stack([b - a, c - b, a - c]), axis=2), axis=0)
    masks["spike through the body"] = longest > 20 * np.median(longest)
    # Connected parts by shared vertices: the smallest is the speck.
    parent = np.arange(len(v))

    def root(i):
        while parent[i] != i:
            parent[i] = parent[parent[i]]
            i = parent[i]
        return i

    for x, y, z in f:
        rx, ry, rz = root(x), root(y), root(z)
        parent[ry] = rx
        parent[root(rz)] = rx
    comp = np.array([root(i) for i in f[:, 0]])
    labels, sizes = np.unique(comp, return_counts=True)
    masks["speck (a second body)"] = comp == labels[np.argmin(sizes)] if len(labels) > 1 else np.zeros(len(f), bool)
    return masks


def shaded(v, f, rgb):
    n = np.cross(v[f[:, 1]] - v[f[:, 0]], v[f[:, 2]] - v[f[:, 0]])
    n /= np.maximum(np.linalg.norm(n, axis=1, keepdims=True), 1e-300)
    lam = np.clip(n @ LIGHT, 0.0, 1.0)
    return np.clip(np.asarray(rgb)[None, :] * (0.35 + 0.65 * lam)[:, None], 0, 1)


def panel(ax, v, f, colours, title, lo, hi, edges=False):
    tri = v[f]
    col = Poly3DCollection(tri, facecolors=colours, edgecolors=(0, 0, 0, 0.25) if edges else "none",
                           linewidths=0.15 if edges else 0.0)
    ax.add_collection3d(col)
    mid, half = 0.5 * (lo + hi), 0.5 * (hi - lo).max()
    ax.set_xlim(mid[0] - half, mid[0] + half)
    ax.set_ylim(mid[1] - half, mid[1] + half)
    ax.set_zlim(mid[2] - half, mid[2] + half)
    ax.set_box_aspect((1, 1, 1), zoom=1.45)
    ax.view_init(ELEV, AZIM)
    ax.set_axis_off()
    ax.set_title(title, fontsize=9)


def main():
    raw_path, prepared_path, solved_path, scene_path, out = sys.argv[1:6]
    rv, rf = read_stl(raw_path)
    rv = rv * 1e-3  # mm -> m, to share the other panels' axes
    masks = find_defects(rv, rf)
    pv, pf = read_obj(prepared_path)
    sv, sf = read_obj(solved_path)
    base = np.array([0.80, 0.62, 0.55])
    colours = shaded(rv, rf, base)
    marks = {"zero-area faces": "tab:purple", "fin (non-manifold edge)": "tab:red", "hole rim": "tab:blue",
             "flipped patch (rim)": "tab:orange", "spike through the body": "magenta", "speck (a second body)": "tab:green"}
    scene = json.load(open(scene_path))
    region = scene["operating_region"]["sphere"]
    held = scene["operating_region"]["supported"]["sphere"]

    fig = plt.figure(figsize=(12, 3.9), dpi=100)
    ax = fig.add_subplot(1, 3, 1, projection="3d")
    ax.computed_zorder = False
    for name, colour in marks.items():
        colours[masks[name]] = matplotlib.colors.to_rgb(colour)
    lo, hi = pv.min(axis=0), pv.max(axis=0)  # one camera: the body's box (the speck lies outside it)
    panel(ax, rv, rf, colours, f"raw segmentation: {len(rf):,} triangles (mm)", lo, hi)
    for name, colour in marks.items():
        m = masks[name]
        if m.any():
            c = rv[rf[m]].reshape(-1, 3).mean(axis=0)
            away = " (off the picture)" if (c < lo).any() or (c > hi).any() else ""
            ax.scatter(*c, s=90, facecolors="none", edgecolors=colour, linewidths=1.8, zorder=10,
                       label=f"{name}: {int(m.sum())} face{'s' if m.sum() > 1 else ''}{away}")
    fig.legend(loc="lower left", fontsize=7, frameon=False, ncol=3, bbox_to_anchor=(0.01, 0.0))

    panel(fig.add_subplot(1, 3, 2, projection="3d"), pv, pf, shaded(pv, pf, base),
          f"bemsurg prepare --units mm: {len(pf):,} elements", lo, hi, edges=True)

    centroids = sv[sf].mean(axis=1)
    colours = shaded(sv, sf, base)
    near = lambda s: np.linalg.norm(centroids - np.array(s["center"]), axis=1) <= s["radius"]  # noqa: E731
    colours[near(region)] = shaded(sv, sf, [0.95, 0.80, 0.30])[near(region)]
    colours[near(held)] = shaded(sv, sf, [0.45, 0.55, 0.85])[near(held)]
    panel(fig.add_subplot(1, 3, 3, projection="3d"), sv, sf, colours,
          f"the scene's solved mesh: {len(sf):,} elements\n(yellow: operating region, blue: held)", lo, hi, edges=True)
    fig.subplots_adjust(left=0.0, right=1.0, top=0.9, bottom=0.08, wspace=0.0)
    buffer = io.BytesIO()
    fig.savefig(buffer, format="png")
    im = Image.open(buffer).convert("RGB")
    # FASTOCTREE keeps the markers' colours (a median cut merged them into the organ's shades).
    im.quantize(colors=256, method=Image.Quantize.FASTOCTREE).save(out, optimize=True)


if __name__ == "__main__":
    main()
