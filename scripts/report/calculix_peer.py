"""The finite-element peer of the benchmark report (issues 24 and 38; scripts/report/parts/peer.py):
CalculiX (Debian's calculix-ccx) on quadratic tetrahedra (C3D10) that Gmsh meshes from one fixed surface.

  calculix_peer.py mesh --surface BODY.obj --out DIR --h H --h-edge HE
                        [--tool-displacement DX,DY,DZ] [--clamp-within TRIANGLES.csv]
                        [--young E --poisson NU --density RHO --gravity G]

BODY.obj is bench_organ_gravity's labelled surface: its faces in groups "held" (clamped), "tool"
(the flat tool's footprint, moved by --tool-displacement) and "free". Each group goes to Gmsh as
a discrete surface of its own, so that the rims between them are mesh curves (as bemsurg's
remesher keeps the rim of a flat face and its conforming rules split along a sphere, issue 38):
both sides then hold the same area, and the held nodes are exactly those of the held surfaces.
Gmsh re-parametrises the surfaces and meshes the volume with size H, HE within a band around the
rims, second order; the script writes DIR/job.inp and DIR/mesh.npz (nodes, the 6-node surface
triangles, the held and tool nodes). Then ``ccx -i job`` (run by the part, which times it) writes
job.dat; ``read_result`` parses it and ``evaluate`` interpolates the surface displacement at any
surface point. --clamp-within keeps only the held nodes whose (x, y) lie in one of the listed
triangles (on the plane z = 0): the control that clamps the finite-element model where bemsurg's
earlier remeshes clamped it. Gravity pulls along -z.

Needs /usr/bin/python3 with Debian's python3-gmsh for ``mesh``; the rest needs numpy only.
"""

import argparse
import json
import math
import re
import sys
import time
from pathlib import Path

import numpy as np

# Gmsh's 10-node tetrahedron (element type 11) numbers its mid-edge nodes 4:(0,1) 5:(1,2) 6:(0,2)
# 7:(0,3) 8:(2,3) 9:(1,3) (Gmsh manual, "Node ordering"); CalculiX's C3D10, as Abaqus', has
# 8:(1,3) and 9:(2,3) (ccx 2.20 manual, section 6.2.6). So the last two swap.
GMSH_TO_CCX_TET10 = [0, 1, 2, 3, 4, 5, 6, 7, 9, 8]
CCX_TET10_EDGES = [(0, 1), (1, 2), (2, 0), (0, 3), (1, 3), (2, 3)]  # of nodes 4..9
PLANE_TOLERANCE = 1e-7  # m: a point on the plane z = 0 (bench_organ_gravity's patch test)
LABELS = ("free", "held", "tool")  # the OBJ's groups, in bench_organ_gravity's order
# Creases sharper than this split the free group further (the brain's folds): one surface of the
# whole folded body parametrises badly (Gmsh took 67 s instead of 4 at h = 12 mm). _parts says how.
FEATURE_ANGLE = 40.0
MAX_PART_TRIANGLES = 800  # larger parts are cut into sectors (_parts)


def read_labelled_obj(path):
    """Vertices (N x 3), faces (M x 3, 0-based) and each face's label (index into LABELS)."""
    verts, faces, labels, label = [], [], [], 0
    for line in Path(path).read_text().splitlines():
        if line.startswith("v "):
            verts.append([float(x) for x in line.split()[1:4]])
        elif line.startswith("g "):
            label = LABELS.index(line.split()[1])
        elif line.startswith("f "):
            faces.append([int(x.split("/")[0]) - 1 for x in line.split()[1:4]])
            labels.append(label)
    return np.array(verts), np.array(faces, dtype=np.int64), np.array(labels)


def surface_points(path):
    """Centroids, areas and labels of the surface's triangles: the fixed points the FE levels are compared at."""
    v, f, lab = read_labelled_obj(path)
    t = v[f]
    area = 0.5 * np.linalg.norm(np.cross(t[:, 1] - t[:, 0], t[:, 2] - t[:, 0]), axis=1)
    return t.mean(axis=1), area, lab


def _rim_size_field(gmsh, label_of, h, h_edge, band):
    """Gmsh's own Distance and Threshold fields: h_edge on the rims (the curves between surfaces of
    different labels), growing linearly to h at the distance `band`. A Python size callback did the
    same with one k-d tree query per call: about 219,000 calls, 15.9 s of a 20 s mesh of the liver's
    coarsest level, nearly all of it numpy's per-call overhead. Returns the field, or None without rims."""
    rims, longest = [], 0.0
    for _, c in gmsh.model.getEntities(1):
        up, _ = gmsh.model.getAdjacencies(1, c)
        if len({label_of.get(int(s)) for s in up}) > 1:
            rims.append(c)
            tags, xyz, _ = gmsh.model.mesh.getNodes(1, c, True, False)
            at = dict(zip(tags, np.asarray(xyz).reshape(-1, 3)))
            types, _, nodes = gmsh.model.mesh.getElements(1, c)
            for t, ns in zip(types, nodes):  # the input's own segments along the curve
                if t == 1:
                    longest = max(longest, sum(float(np.linalg.norm(at[a] - at[b])) for a, b in np.asarray(ns).reshape(-1, 2)))
    if not rims:
        return None
    distance = gmsh.model.mesh.field.add("Distance")
    gmsh.model.mesh.field.setNumbers(distance, "CurvesList", rims)
    # Points spaced at most h_edge / 4 on the longest rim curve (uniformly in its parameter).
    gmsh.model.mesh.field.setNumber(distance, "NumPointsPerCurve", max(20, int(math.ceil(4.0 * longest / h_edge))))
    threshold = gmsh.model.mesh.field.add("Threshold")
    gmsh.model.mesh.field.setNumber(threshold, "InField", distance)
    for k, val in (("SizeMin", h_edge), ("SizeMax", h), ("DistMin", 0.0), ("DistMax", band)):
        gmsh.model.mesh.field.setNumber(threshold, k, val)
    return threshold


def _parts(v, f, lab, feature_angle):
    """Each face's part: the labels' regions, the free one split further at creases sharper than the
    feature angle (flood fill across smoother edges), as bemsurg's remesher does
    (graded_remesher.cpp, surface_of_faces): an edge with a corner on a label's rim is never a
    crease, since the triangles along a flat face's rim zigzag at 40-60 degrees, and Gmsh, given
    those as creases, cut the sides into slivers (6 mm took 385 s instead of seconds)."""
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import connected_components
    n = np.cross(v[f[:, 1]] - v[f[:, 0]], v[f[:, 2]] - v[f[:, 0]])
    n /= np.linalg.norm(n, axis=1)[:, None]
    edges = {}
    for k, tri in enumerate(f.tolist()):
        for a, b in ((tri[0], tri[1]), (tri[1], tri[2]), (tri[2], tri[0])):
            edges.setdefault((min(a, b), max(a, b)), []).append(k)
    on_rim = np.zeros(len(v), bool)
    for (a, b), fs in edges.items():
        if len(fs) == 2 and lab[fs[0]] != lab[fs[1]]:
            on_rim[[a, b]] = True
    cos = math.cos(math.radians(feature_angle))
    rows, cols = [], []
    for (a, b), fs in edges.items():
        if len(fs) != 2 or lab[fs[0]] != lab[fs[1]]:
            continue
        if lab[fs[0]] == 0 and not (on_rim[a] or on_rim[b]) and n[fs[0]] @ n[fs[1]] < cos:
            continue  # a crease of the free part
        rows.append(fs[0])
        cols.append(fs[1])
    graph = coo_matrix((np.ones(len(rows)), (rows, cols)), shape=(len(f), len(f)))
    part = connected_components(graph, directed=False)[1]
    # Large parts cut into sectors about their centroid: Gmsh evaluates a size field on a
    # re-parametrised surface at a cost that grows with its triangles (the brain's flat face, 5,800
    # of them, took minutes to mesh graded, seconds in eight sectors).
    c = v[f].mean(axis=1)
    out, next_id = part.copy(), part.max() + 1
    for k in np.unique(part):
        sel = np.nonzero(part == k)[0]
        if len(sel) <= MAX_PART_TRIANGLES:
            continue
        centre = c[sel].mean(axis=0)
        normal = n[sel].sum(axis=0)
        normal /= np.linalg.norm(normal)
        e1 = np.cross(normal, [1.0, 0.0, 0.0] if abs(normal[0]) < 0.9 else [0.0, 1.0, 0.0])
        e1 /= np.linalg.norm(e1)
        e2 = np.cross(normal, e1)
        d = c[sel] - centre
        sectors = int(math.ceil(len(sel) / MAX_PART_TRIANGLES))
        s = np.minimum((np.arctan2(d @ e2, d @ e1) + math.pi) / (2 * math.pi) * sectors, sectors - 1).astype(int)
        out[sel] = np.where(s == 0, k, next_id + s - 1)
        next_id += sectors - 1
    return out


def _add_labelled_surfaces(gmsh, v, f, lab):
    """Each part (_parts) as a discrete surface; createTopology makes their borders curves, which
    classifySurfaces (no angle of its own) keeps, and createGeometry re-parametrises. Returns the
    label of each surface."""
    part = _parts(v, f, lab, FEATURE_ANGLE)
    parts = np.unique(part)
    for k in parts:
        gmsh.model.addDiscreteEntity(2, int(k) + 1)
    gmsh.model.mesh.addNodes(2, int(parts[0]) + 1, list(range(1, len(v) + 1)), v.ravel().tolist())
    for k in parts:
        sel = np.nonzero(part == k)[0]
        gmsh.model.mesh.addElementsByType(int(k) + 1, 2, (sel + 1).tolist(), (f[sel] + 1).ravel().tolist())
    gmsh.model.mesh.reclassifyNodes()
    gmsh.model.mesh.createTopology()
    gmsh.model.mesh.classifySurfaces(math.pi, True, True, math.pi)
    gmsh.model.mesh.createGeometry()
    from scipy.spatial import cKDTree
    tree = cKDTree(v[f].mean(axis=1))
    label_of = {}
    for _, tag in gmsh.model.getEntities(2):
        _, _, nodes = gmsh.model.mesh.getElements(2, tag)
        if not len(nodes) or not len(nodes[0]):
            continue
        xyz = np.array([gmsh.model.mesh.getNode(int(n))[0] for n in nodes[0][:3]])
        label_of[tag] = int(lab[tree.query(xyz.mean(axis=0))[1]])
    return label_of


def _nodes_of(gmsh, label_of, label, index):
    """The (renumbered) nodes on the surfaces of one label, their rims included."""
    out = set()
    for tag, lb in label_of.items():
        if lb == label:
            tags, _, _ = gmsh.model.mesh.getNodes(2, tag, True, False)
            out.update(index[np.asarray(tags, dtype=np.int64)].tolist())
    return np.array(sorted(out), dtype=np.int64)


def _surface_triangles(gmsh, label_of, label):
    """The Gmsh node tags (m x 6) of the 6-node triangles on the surfaces of one label."""
    out = [np.asarray(gmsh.model.mesh.getElements(2, tag)[2][0], dtype=np.int64).reshape(-1, 6)
           for tag, lb in label_of.items() if lb == label]
    return np.concatenate(out) if out else np.zeros((0, 6), dtype=np.int64)


# A 6-point rule of degree 4 on the reference triangle (Dunavant 1985): points (r, s), weights summing to 1.
_TRI_A, _TRI_B, _TRI_WA, _TRI_WB = 0.445948490915965, 0.091576213509771, 0.223381589678011, 0.109951743655322
_TRI_RULE = [((_TRI_A, _TRI_A), _TRI_WA), ((1 - 2 * _TRI_A, _TRI_A), _TRI_WA), ((_TRI_A, 1 - 2 * _TRI_A), _TRI_WA),
             ((_TRI_B, _TRI_B), _TRI_WB), ((1 - 2 * _TRI_B, _TRI_B), _TRI_WB), ((_TRI_B, 1 - 2 * _TRI_B), _TRI_WB)]


def curved_area(xyz, tris6):
    """The area of 6-node triangles (Gmsh order: corners, then mid-edges 01, 12, 20) as the finite
    elements see it: their quadratic geometry, whose mid-edge nodes lie on the surface's curves, so
    that a held disc's rim is followed far closer than by the corners' chords."""
    if len(tris6) == 0:
        return 0.0
    p = xyz[tris6]  # (m, 6, 3)
    total = 0.0
    for (r, t), w in _TRI_RULE:
        l0, l1, l2 = 1 - r - t, r, t
        d_r = [-(4 * l0 - 1), 4 * l1 - 1, 0.0, 4 * (l0 - l1), 4 * l2, -4 * l2]  # dN/dr (dl0/dr = -1, dl1/dr = 1)
        d_t = [-(4 * l0 - 1), 0.0, 4 * l2 - 1, -4 * l1, 4 * l1, 4 * (l0 - l2)]  # dN/dt (dl0/dt = -1, dl2/dt = 1)
        xr = np.einsum("i,mic->mc", np.array(d_r), p)
        xt = np.einsum("i,mic->mc", np.array(d_t), p)
        total += 0.5 * w * np.linalg.norm(np.cross(xr, xt), axis=1).sum()
    return float(total)


def _inside_triangles(xy, tris):
    """Whether each 2-D point lies in one of the triangles (rows x0,y0,z0,...: their (x, y))."""
    inside = np.zeros(len(xy), bool)
    a, b, c = tris[:, 0:2], tris[:, 3:5], tris[:, 6:8]
    for k in range(len(tris)):
        d = np.stack([((q - p)[0] * (xy[:, 1] - p[1]) - (q - p)[1] * (xy[:, 0] - p[0]))
                      for p, q in ((a[k], b[k]), (b[k], c[k]), (c[k], a[k]))], axis=1)
        scale = 1e-9 * max(np.abs(d).max(), 1e-300)
        inside |= (d >= -scale).all(axis=1) | (d <= scale).all(axis=1)
    return inside


# Sizes tried, in turn, when Gmsh fails on one (its 2-D mesher can leave two neighbouring surfaces'
# triangles overlapping at one size and not at the next: the brain at exactly h = 4.25 mm, while
# 4.1, 4.2, 4.3 and 4.4 mm mesh): a level is meshed at the first that works, 1-2 % off the size asked
# for, and says which (the ladder's Richardson estimate uses the sizes actually meshed).
SIZE_RETRIES = (1.0, 0.99, 1.01, 0.98, 1.02)


def mesh(surface, out, h, h_edge, young, poisson, density, gravity, tool_displacement=(0.0, 0.0, 0.0), clamp_within=None):
    """Gmsh: volume mesh of the closed labelled surface, written as a CalculiX deck. Returns a summary dict
    (with the sizes meshed: h and h_edge times the first factor of SIZE_RETRIES that Gmsh meshes)."""
    failures = []
    for factor in SIZE_RETRIES:
        try:
            info = _mesh_at(surface, out, h * factor, h_edge * factor, young, poisson, density, gravity, tool_displacement,
                            clamp_within)
        except Exception as e:  # noqa: BLE001: Gmsh raises plain Exception; tried at the next size, reported if none works
            failures.append(f"h = {h * factor:.6g} m: {e}")
            continue
        info.update(size_factor=factor, h_asked=h, failed_sizes=failures)
        return info
    raise RuntimeError("calculix_peer: Gmsh failed at every size tried:\n" + "\n".join(failures))


def _mesh_at(surface, out, h, h_edge, young, poisson, density, gravity, tool_displacement, clamp_within):
    """mesh() at one pair of sizes."""
    import gmsh  # Debian's python3-gmsh: imported here so that the rest works without it

    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    start = time.monotonic()
    v, f, lab = read_labelled_obj(surface)
    gmsh.initialize([], False)
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        label_of = _add_labelled_surfaces(gmsh, v, f, lab)
        loop = gmsh.model.geo.addSurfaceLoop([t for _, t in gmsh.model.getEntities(2)])
        gmsh.model.geo.addVolume([loop])
        gmsh.model.geo.synchronize()
        field = _rim_size_field(gmsh, label_of, h, h_edge, band=3.0 * h)  # grade from h_edge on the rims to h at 3 h
        if field is not None:
            gmsh.model.mesh.field.setAsBackgroundMesh(field)
        for k, val in (("Mesh.MeshSizeFromPoints", 0), ("Mesh.MeshSizeFromCurvature", 0), ("Mesh.MeshSizeExtendFromBoundary", 0),
                       ("Mesh.MeshSizeMin", h_edge), ("Mesh.MeshSizeMax", h), ("Mesh.Algorithm", 6), ("Mesh.Algorithm3D", 1),
                       ("Mesh.ElementOrder", 2), ("Mesh.SecondOrderLinear", 0), ("Mesh.Optimize", 1)):
            gmsh.option.setNumber(k, val)
        gmsh.model.mesh.generate(3)
        tags, xyz, _ = gmsh.model.mesh.getNodes()
        xyz = xyz.reshape(-1, 3)
        _, tet_nodes = gmsh.model.mesh.getElementsByType(11)
        _, tri_nodes = gmsh.model.mesh.getElementsByType(9)
        # Renumber the nodes 0..N-1 (ccx wants 1..N; Gmsh's tags may have gaps).
        index = np.zeros(int(tags.max()) + 1, dtype=np.int64)
        index[tags.astype(np.int64)] = np.arange(len(tags))
        held = _nodes_of(gmsh, label_of, LABELS.index("held"), index)
        tool = _nodes_of(gmsh, label_of, LABELS.index("tool"), index)
        held_tris = _surface_triangles(gmsh, label_of, LABELS.index("held"))
        tool_tris = _surface_triangles(gmsh, label_of, LABELS.index("tool"))
    finally:
        gmsh.finalize()
    mesh_s = time.monotonic() - start
    tets = index[tet_nodes.astype(np.int64)].reshape(-1, 10)[:, GMSH_TO_CCX_TET10]
    tris = index[tri_nodes.astype(np.int64)].reshape(-1, 6)
    tets = _positive(xyz, tets)
    _check_mid_edges(xyz, tets)
    straightened = _untangle(xyz, tets)
    # After the straightening: Gmsh may leave a mid-edge node of a flat face unplaced (1e21) where
    # its projection fails; the straightened model is what ccx solves and what holds the area.
    held_area = curved_area(xyz, index[held_tris])
    tool_area = curved_area(xyz, index[tool_tris])
    if clamp_within is not None:
        tri = np.loadtxt(clamp_within, delimiter=",", skiprows=1, ndmin=2)
        held = held[_inside_triangles(xyz[held, :2], tri)]
    surface_nodes = np.unique(tris)
    held_load = gravity_on_nodes(xyz, tets, held, density, gravity)
    tool_load = gravity_on_nodes(xyz, tets, tool, density, gravity)
    _write_deck(out / "job.inp", xyz, tets, held, tool, surface_nodes, young, poisson, density, gravity, tool_displacement)
    np.savez_compressed(out / "mesh.npz", xyz=xyz, tris=tris, surface_nodes=surface_nodes, held=held, tool=tool)
    return {"peak_rss_bytes": peak_rss_bytes(), "nodes": len(xyz), "elements": len(tets), "surface_triangles": len(tris),
            "patch_nodes": len(held), "tool_nodes": len(tool), "held_area_m2": held_area, "tool_area_m2": tool_area,
            "straightened_elements": straightened, "patch_node_load_n": held_load, "tool_node_load_n": tool_load,
            "mesh_s": mesh_s, "h": h, "h_edge": h_edge}


def peak_rss_bytes(status="/proc/self/status"):
    """This process's own peak resident memory (VmHWM). Not getrusage's ru_maxrss: Linux carries the
    high-water mark across fork and exec, so a child of a large driver would report the driver's."""
    m = re.search(r"^VmHWM:\s*(\d+) kB", Path(status).read_text(), re.M)
    return int(m.group(1)) * 1024 if m else None


def run_ccx(workdir):
    """ccx -i job in workdir: wall seconds and ccx's peak memory (ru_maxrss of a child of this small
    process, so that the floor it inherits is this process's, not a large caller's)."""
    import os
    import subprocess
    start = time.monotonic()
    with open(Path(workdir) / "ccx.log", "w") as log:
        proc = subprocess.Popen(["ccx", "-i", "job"], cwd=workdir, stdout=log, stderr=subprocess.STDOUT)
        _, status, usage = os.wait4(proc.pid, 0)
    seconds = time.monotonic() - start
    code = os.waitstatus_to_exitcode(status)
    if code != 0:
        tail = "\n".join((Path(workdir) / "ccx.log").read_text().splitlines()[-12:])
        raise RuntimeError(f"calculix_peer: ccx exited with {code} in {workdir}:\n{tail}")
    return {"ccx_s": seconds, "peak_rss_bytes": usage.ru_maxrss * 1024}


def _positive(xyz, tets):
    """ccx needs a positive Jacobian: node 3 on the side of face 0-1-2 its right-hand normal points to."""
    p = xyz[tets[:, :4]]
    det = np.einsum("ij,ij->i", np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]), p[:, 3] - p[:, 0])
    flip = det < 0
    if flip.any():  # swap corners 1, 2 and with them the mid-edge nodes (0,1)<->(0,2), (1,3)<->(2,3)
        tets = tets.copy()
        tets[flip] = tets[flip][:, [0, 2, 1, 3, 6, 5, 4, 7, 9, 8]]
    return tets


def _check_mid_edges(xyz, tets):
    """The renumbering is right when every mid-edge node lies near the middle of its ccx edge."""
    p = xyz[tets]
    for k, (a, b) in enumerate(CCX_TET10_EDGES):
        mid = 0.5 * (p[:, a] + p[:, b])
        length = np.linalg.norm(p[:, a] - p[:, b], axis=1)
        off = np.linalg.norm(p[:, 4 + k] - mid, axis=1) / length
        if np.median(off) > 1e-3:  # a wrong numbering puts most of them a quarter edge or more away
            raise RuntimeError(f"calculix_peer: mid-edge node {5 + k} is not on edge {a + 1}-{b + 1} (C3D10 numbering)")


# Where the Jacobian of a curved C3D10 is checked: its corners and the 4-point rule ccx integrates with.
_A, _B = 0.1381966011250105, 0.5854101966249685
_SAMPLES = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1], [_A, _A, _A], [_B, _A, _A], [_A, _B, _A], [_A, _A, _B]])


def _shape(r, s, t):
    """C3D10 shape functions (10) and their derivatives d/d(r, s, t) (10 x 3) at one point."""
    lam = np.array([1 - r - s - t, r, s, t])
    dlam = np.array([[-1, -1, -1], [1, 0, 0], [0, 1, 0], [0, 0, 1]], float)  # dL_i / d(r, s, t)
    n = [lam[i] * (2 * lam[i] - 1) for i in range(4)] + [4 * lam[a] * lam[b] for a, b in CCX_TET10_EDGES]
    dn = [(4 * lam[i] - 1) * dlam[i] for i in range(4)] + [4 * (lam[a] * dlam[b] + lam[b] * dlam[a]) for a, b in CCX_TET10_EDGES]
    return np.array(n), np.array(dn)


def _dets(xyz, tets, samples):
    """det J of each C3D10 (rows) at each sample point (columns)."""
    p = xyz[tets]  # (n, 10, 3)
    return np.stack([np.linalg.det(np.einsum("nic,id->ncd", p, _shape(*q)[1])) for q in samples], axis=1)


def _jacobian_dets(xyz, tets):
    """det J at the corners and the 4 Gauss points over the straight tet's det."""
    c = xyz[tets[:, :4]]
    lin = np.einsum("ij,ij->i", np.cross(c[:, 1] - c[:, 0], c[:, 2] - c[:, 0]), c[:, 3] - c[:, 0])
    return _dets(xyz, tets, _SAMPLES) / lin[:, None]


def gravity_on_nodes(xyz, tets, nodes, density, gravity):
    """The consistent gravity load (N, along -z, as a magnitude) that lands on the given nodes: ccx's RF
    there is the internal force alone, so RF + this load is what balances the weight."""
    dets = _dets(xyz, tets, _SAMPLES[4:])
    mask = np.zeros(len(xyz), bool)
    mask[nodes] = True
    total = 0.0
    for k, q in enumerate(_SAMPLES[4:]):
        n, _ = _shape(*q)
        total += ((dets[:, k:k + 1] / 24.0) * n[None, :] * mask[tets]).sum()  # 4-point rule: weights 1/24
    return density * gravity * total


def _untangle(xyz, tets, floor=0.05):
    """Gmsh curves the boundary elements onto the surface; on a coarse mesh of a folded surface a
    few of them fold over (ccx: "nonpositive jacobian"). Their mid-edge nodes go back to the
    straight edges' middles (the surface is then flat there, within h^2 / 8 of the true one)."""
    moved = set()
    for _ in range(10):
        bad = np.nonzero(_jacobian_dets(xyz, tets).min(axis=1) < floor)[0]
        if len(bad) == 0:
            return len(moved)
        for k, (a, b) in enumerate(CCX_TET10_EDGES):
            xyz[tets[bad, 4 + k]] = 0.5 * (xyz[tets[bad, a]] + xyz[tets[bad, b]])
        moved.update(bad.tolist())
    raise RuntimeError("calculix_peer: elements still tangled after straightening their edges")


def _write_deck(path, xyz, tets, fixed, tool, surface_nodes, young, poisson, density, gravity, tool_displacement):
    if len(fixed) == 0:
        raise RuntimeError("calculix_peer: no node lies on the held surface")
    lines = ["** bemsurg organ peer (scripts/report/calculix_peer.py): C3D10 from Gmsh", "*NODE, NSET=NALL"]
    # ccx reads at most 20 characters a field: 13 significant digits fit.
    lines += [f"{i + 1}, {x:.12e}, {y:.12e}, {z:.12e}" for i, (x, y, z) in enumerate(xyz.tolist())]
    lines.append("*ELEMENT, TYPE=C3D10, ELSET=EALL")
    # Eleven entries: a data line holds at most 16, so one line each.
    lines += [f"{e + 1}, " + ", ".join(str(n + 1) for n in row) for e, row in enumerate(tets.tolist())]
    lines += _nset("FIX", fixed) + _nset("NSURF", surface_nodes) + (_nset("TOOL", tool) if len(tool) else [])
    lines += ["*MATERIAL, NAME=TISSUE", "*ELASTIC", f"{young!r}, {poisson!r}", "*DENSITY", f"{density!r}",
              "*SOLID SECTION, ELSET=EALL, MATERIAL=TISSUE",
              "*BOUNDARY", "FIX, 1, 3"]
    if len(tool):  # the tool's footprint moves with the tool (bonded: all three components prescribed)
        lines += [f"TOOL, {k + 1}, {k + 1}, {float(d)!r}" for k, d in enumerate(tool_displacement)]
    lines += ["*STEP", "*STATIC",
              "*DLOAD", f"EALL, GRAV, {gravity!r}, 0., 0., -1.",
              "*NODE PRINT, NSET=NSURF", "U",
              "*NODE PRINT, NSET=FIX, TOTALS=ONLY", "RF"]
    if len(tool):
        lines += ["*NODE PRINT, NSET=TOOL, TOTALS=ONLY", "RF"]
    lines += ["*EL PRINT, ELSET=EALL, TOTALS=ONLY", "EVOL", "*END STEP", ""]
    Path(path).write_text("\n".join(lines))


def _nset(name, nodes):
    ids = [str(n + 1) for n in nodes]
    return [f"*NSET, NSET={name}"] + [", ".join(ids[i:i + 16]) for i in range(0, len(ids), 16)]


def read_result(workdir):
    """job.dat: the surface nodes' displacements (N x 3, NaN off the surface), the total reaction
    force on each constrained set ({"FIX": (3,), "TOOL": (3,)}: ccx's RF, the internal force at
    those nodes) and the total volume ccx integrated."""
    d = np.load(Path(workdir) / "mesh.npz")
    u = np.full((len(d["xyz"]), 3), np.nan)
    reactions, volume, section, rf_set = {}, None, None, None
    for line in (Path(workdir) / "job.dat").read_text().splitlines():
        s = line.strip()
        if not s:
            continue
        if re.match(r"^[a-z]", s):
            section = "u" if s.startswith("displacements") else "rf" if s.startswith("total force") else \
                "vol" if s.startswith("total volume") else None
            if section == "rf":
                m = re.search(r"for set (\S+)", s)
                rf_set = m.group(1).upper() if m else "FIX"
            continue
        v = s.split()
        if section == "u":
            u[int(v[0]) - 1] = [float(x) for x in v[1:4]]
        elif section == "rf":
            reactions[rf_set] = np.array([float(x) for x in v[:3]])
        elif section == "vol":
            volume = float(v[0])
    if "FIX" not in reactions or volume is None or np.isnan(u[d["surface_nodes"]]).any() or \
            (len(d["tool"]) and "TOOL" not in reactions):
        raise RuntimeError(f"calculix_peer: {workdir}/job.dat lacks displacements, a reaction or the volume")
    return u, reactions, volume


def evaluate(workdir, u, points, k=8, chunk=2048):
    """The displacement at surface points: the closest of the k surface triangles whose centroids
    are nearest, its quadratic (6-node) interpolation at the point's projection."""
    d = np.load(Path(workdir) / "mesh.npz")
    xyz, tris = d["xyz"], d["tris"]
    a, b, c = xyz[tris[:, 0]], xyz[tris[:, 1]], xyz[tris[:, 2]]
    cen = (a + b + c) / 3
    cc = np.einsum("ij,ij->i", cen, cen)
    out = np.empty((len(points), 3))
    for s in range(0, len(points), chunk):
        q = points[s:s + chunk]
        d2 = cc[None, :] - 2 * q @ cen.T
        cand = np.argpartition(d2, min(k, len(cen) - 1), axis=1)[:, :k]  # (m, k)
        lam, dist = _project(q[:, None, :], a[cand], b[cand], c[cand])
        best = np.argmin(dist, axis=1)
        rows = np.arange(len(q))
        t = tris[cand[rows, best]]  # (m, 6)
        l0, l1, l2 = (lam[rows, best, i] for i in range(3))
        n = np.stack([l0 * (2 * l0 - 1), l1 * (2 * l1 - 1), l2 * (2 * l2 - 1), 4 * l0 * l1, 4 * l1 * l2, 4 * l2 * l0], axis=1)
        out[s:s + chunk] = np.einsum("mi,mij->mj", n, u[t])
    return out


def _project(p, a, b, c):
    """Barycentric coordinates of p's projection on triangles abc, clipped into the triangle (a
    close stand-in for the closest point near the surface), and the distance to that point."""
    e0, e1, w = b - a, c - a, p - a
    d00, d01, d11 = (e0 * e0).sum(-1), (e0 * e1).sum(-1), (e1 * e1).sum(-1)
    d20, d21 = (w * e0).sum(-1), (w * e1).sum(-1)
    den = d00 * d11 - d01 * d01
    l1 = (d11 * d20 - d01 * d21) / den
    l2 = (d00 * d21 - d01 * d20) / den
    lam = np.clip(np.stack([1 - l1 - l2, l1, l2], axis=-1), 0, None)
    lam /= lam.sum(-1, keepdims=True)
    x = lam[..., :1] * a + lam[..., 1:2] * b + lam[..., 2:] * c
    return lam, np.linalg.norm(p - x, axis=-1)


def relative_l2(u, ref, weights):
    """sqrt(sum w |u - ref|^2 / sum w |ref|^2): the report's surface displacement error."""
    return float(math.sqrt((weights * ((u - ref) ** 2).sum(1)).sum() / (weights * (ref ** 2).sum(1)).sum()))


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    sub = ap.add_subparsers(dest="command", required=True)
    m = sub.add_parser("mesh")
    m.add_argument("--surface", required=True)
    m.add_argument("--out", required=True)
    m.add_argument("--h", type=float, required=True)
    m.add_argument("--h-edge", type=float, required=True)
    m.add_argument("--tool-displacement", default="0,0,0", help="DX,DY,DZ (m): the tool footprint's displacement")
    m.add_argument("--clamp-within", help="CSV of triangles (x0,y0,z0,...,z2): hold only the held nodes inside them")
    m.add_argument("--young", type=float, default=3000.0)
    m.add_argument("--poisson", type=float, default=0.45)
    m.add_argument("--density", type=float, default=1000.0)
    m.add_argument("--gravity", type=float, default=9.81)
    c = sub.add_parser("ccx")
    c.add_argument("--dir", required=True)
    a = ap.parse_args()
    if a.command == "ccx":
        print(json.dumps(run_ccx(a.dir)))
        return 0
    tool = [float(x) for x in a.tool_displacement.split(",")]
    info = mesh(a.surface, a.out, a.h, a.h_edge, a.young, a.poisson, a.density, a.gravity, tool, a.clamp_within)
    print(json.dumps(info))
    return 0


if __name__ == "__main__":
    sys.exit(main())
