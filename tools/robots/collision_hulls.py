#!/usr/bin/env python3
"""Compute the shipped arms' collision geometry once, from the published meshes: a few convex
pieces per link where one convex hull would fill a real opening (the forearm's fork), one hull
elsewhere.

    python3 tools/robots/collision_hulls.py --abb ABB_GIT_DIR --ur UR_GIT_DIR          # write
    python3 tools/robots/collision_hulls.py --abb ABB_GIT_DIR --ur UR_GIT_DIR --check  # verify only
    ... --only abb_irb6700_200_260,abb_irb4600_40_255                                  # those robots only

ABB_GIT_DIR / UR_GIT_DIR: git directories (a clone or a bare mirror) of
https://github.com/ros-industrial/abb_experimental and
https://github.com/UniversalRobots/Universal_Robots_ROS2_Description; the files are read at the
pinned commits below with `git show`, so nothing else of the clone matters.

The sources' `collision` meshes are convex hulls already (each fills its hull: volume ratio 1.00),
so the forearm's fork is closed in them. The shape of a link is its `visual` mesh (same origin as
the collision mesh in the source xacro, checked: every visual vertex lies inside the published
collision hull within 5 mm). For every link:

1. the visual mesh's vertices, placed in the link frame of printwatt's URDF by the source's
   `<visual><origin>` (and, for the UR10e base, the fixed base_link -> base_link_inertia turn);
2. an approximate convex decomposition of the visual mesh (CoACD, Wei et al. 2022, PyPI `coacd`,
   concavity threshold CONCAVITY, at most MAX_PIECES pieces, fixed seed);
3. the decomposition is kept when its pieces' volume is at most KEEP_RATIO of the single hull's
   (one hull would fill a real gap); otherwise the link is one hull of the visual mesh;
4. every visual vertex outside all pieces is given to the piece it is least outside of, and each
   piece is then the convex hull of its points, decimated while staying CONSERVATIVE: the hull
   of a greedy subset of the hull's vertices (each step adds the vertex farthest outside), each
   facet moved out by the farthest point beyond it (plus 0.1 mm). A link kept whole is one hull
   of its published collision mesh, the greedy subset (MAX_VERTICES) scaled about its centroid
   by the smallest factor that puts every point inside (plus 0.1 mm). So the union of the written pieces contains the visual
   mesh; how much larger each piece is (scale factor, largest outward offset) is printed and
   written to the README.

The link frames: the joint origins of robots/<name>/robot.urdf are compared with the source's
(SOURCE_JOINTS below, transcribed from the source xacro / yaml at the pinned commit); they must
agree to 1e-9 m / rad (for the UR10e our joint_1 origin folds base_link -> base_link_inertia,
yaw pi, into it, so link_1.. are the source's shoulder_link.. frames).

Writes robots/<name>/collision/<link>-<k>.obj (vertices and triangles of piece k, m, link frame)
and the README there. tools/robots/make_robots.py adds one <collision> element per piece.
Needs numpy, scipy, trimesh, pycollada (the UR and IRB 4600 visual meshes are COLLADA) and coacd.
"""
import math
import os
import struct
import subprocess
import sys

import io

import numpy as np
from scipy.spatial import ConvexHull

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
MAX_VERTICES = 64
# A decomposed link's pieces: the greedy subset's size before its facets are moved out.
PIECE_MAX_VERTICES = 64
PAD_M = 1e-4
CONCAVITY = 0.05
MAX_PIECES = 8
KEEP_RATIO = 0.85
SEED = 1
# An open visual mesh (the IRB 4600's COLLADA) is remeshed closed first (CoACD's manifold step) on a
# grid of this many cells across: fine enough that the prongs keep their shape.
PREPROCESS_RESOLUTION = 120
VISUAL_IN_COLLISION_M = 5e-3

ABB_URL = "https://github.com/ros-industrial/abb_experimental"
ABB_COMMIT = "20b9cf86ad274e4f98540b9c9efe59f94245d2d1"
UR_URL = "https://github.com/UniversalRobots/Universal_Robots_ROS2_Description"
UR_COMMIT = "2221ec0f720fb1af99339eb891639b499b62f1da"
PI = math.pi

# (our link, source file, collision origin xyz, rpy) per robot.  Origins from the source xacro.
ABB6700 = "abb_irb6700_support/meshes/"
ABB4600 = "abb_irb4600_support/meshes/"
UR = "meshes/ur10e/collision/"
ROBOTS = {
    "abb_irb6700_200_260": dict(
        repo="abb", url=ABB_URL, commit=ABB_COMMIT, licence="Apache-2.0 (repository LICENSE; package.xml: Apache 2.0)",
        visual_ext=".stl", decompose=["link_4"],
        xacro="abb_irb6700_support/urdf/irb6700_200_260_macro.xacro",
        links=[("base_link", ABB6700 + "irb6700/collision/base_link.stl", (0, 0, 0), (0, 0, 0)),
               ("link_1", ABB6700 + "irb6700/collision/link_1.stl", (0, 0, 0), (0, 0, 0)),
               ("link_2", ABB6700 + "irb6700_200_260/collision/link_2.stl", (0, 0, 0), (0, 0, 0)),
               ("link_3", ABB6700 + "irb6700_200_260/collision/link_3.stl", (0, 0, 0), (0, 0, 0)),
               ("link_4", ABB6700 + "irb6700_200_260/collision/link_4.stl", (0, 0, 0), (0, 0, 0)),
               ("link_5", ABB6700 + "irb6700/collision/link_5.stl", (0, 0, 0), (0, 0, 0)),
               ("link_6", ABB6700 + "irb6700/collision/link_6.stl", (0, 0, 0), (0, 0, 0))],
        joints=[((0, 0, 0.78), (0, 0, 0)), ((0.32, 0, 0), (0, 0, 0)), ((0, 0, 1.125), (0, 0, 0)),
                ((0, 0, 0.2), (0, 0, 0)), ((1.1425, 0, 0), (0, 0, 0)), ((0.2, 0, 0), (0, 0, 0))],
        note="The balancer's `cylinder` and `piston` links (mimic joints of joint_2) are not modelled."),
    "abb_irb4600_40_255": dict(
        repo="abb", url=ABB_URL, commit=ABB_COMMIT, licence="Apache-2.0 (repository LICENSE; package.xml: Apache2)",
        visual_ext=".dae", decompose=["link_4"],
        xacro="abb_irb4600_support/urdf/irb4600_40_255_macro.xacro",
        links=[("base_link", ABB4600 + "irb4600/collision/base_link.stl", (0, 0, 0), (0, 0, 0)),
               ("link_1", ABB4600 + "irb4600/collision/link_1.stl", (0, 0, 0), (0, 0, 0)),
               ("link_2", ABB4600 + "irb4600_40_255/collision/link_2.stl", (0, 0, 0), (0, 0, 0)),
               ("link_3", ABB4600 + "irb4600_40_255/collision/link_3.stl", (0, 0, 0), (0, 0, 0)),
               ("link_4", ABB4600 + "irb4600_40_255/collision/link_4.stl", (0, 0, 0), (0, 0, 0)),
               ("link_5", ABB4600 + "irb4600_40_255/collision/link_5.stl", (0, 0, 0), (0, 0, 0)),
               ("link_6", ABB4600 + "irb4600_40_255/collision/link_6.stl", (0, 0, 0), (0, 0, 0))],
        joints=[((0, 0, 0.495), (0, 0, 0)), ((0.175, 0, 0), (0, 0, 0)), ((0, 0, 1.095), (0, 0, 0)),
                ((0, 0, 0.175), (0, 0, 0)), ((1.27, 0, 0), (0, 0, 0)), ((0.135, 0, 0), (0, 0, 0))],
        note=""),
    "ur10e": dict(
        repo="ur", url=UR_URL, commit=UR_COMMIT, visual_ext=".dae", decompose=[],
        licence=("BSD-3-Clause (repository LICENSE; the README states that only the UR20 and UR30 meshes fall under "
                 "UR's Terms and Conditions for Use of Graphical Documentation and that all other content is BSD-3-Clause)"),
        xacro="urdf/ur_macro.xacro + config/ur10e/{default_kinematics,visual_parameters,physical_parameters}.yaml",
        # base: collision origin yaw pi in base_link_inertia, itself yaw pi from base_link -> identity.
        links=[("base_link", UR + "base.stl", (0, 0, 0), (0, 0, 0)),
               ("link_1", UR + "shoulder.stl", (0, 0, 0), (0, 0, PI)),
               ("link_2", UR + "upperarm.stl", (0, 0, 0.1762), (PI / 2, 0, -PI / 2)),
               ("link_3", UR + "forearm.stl", (0, 0, 0.0393), (PI / 2, 0, -PI / 2)),
               ("link_4", UR + "wrist1.stl", (0, 0, -0.135), (PI / 2, 0, 0)),
               ("link_5", UR + "wrist2.stl", (0, 0, -0.12), (0, 0, 0)),
               ("link_6", UR + "wrist3.stl", (0, 0, -0.1168), (PI / 2, 0, 0))],
        # joint origins in our URDF: joint_1 = (base_link -> base_link_inertia, yaw pi) o shoulder_pan origin.
        joints=[((0, 0, 0.1807), (0, 0, PI)), ((0, 0, 0), (PI / 2, 0, 0)), ((-0.6127, 0, 0), (0, 0, 0)),
                ((-0.57155, 0, 0.17415), (0, 0, 0)), ((0, -0.11985, 0), (PI / 2, 0, 0)),
                ((0, 0.11655, 0), (PI / 2, PI, PI))],
        note=""),
}


def rpy_matrix(r, p, y):
    cr, sr, cp, sp, cy, sy = math.cos(r), math.sin(r), math.cos(p), math.sin(p), math.cos(y), math.sin(y)
    rx = np.array([[1, 0, 0], [0, cr, -sr], [0, sr, cr]])
    ry = np.array([[cp, 0, sp], [0, 1, 0], [-sp, 0, cp]])
    rz = np.array([[cy, -sy, 0], [sy, cy, 0], [0, 0, 1]])
    return rz @ ry @ rx


def git_bytes(git_dir, commit, path):
    return subprocess.run(["git", "--git-dir", git_dir, "show", "%s:%s" % (commit, path)],
                          check=True, capture_output=True).stdout


def stl_vertices(b):
    if len(b) >= 84:
        n = struct.unpack("<I", b[80:84])[0]
        if 84 + 50 * n == len(b):
            a = np.frombuffer(b[84:], dtype=np.dtype([("n", "<f4", 3), ("v", "<f4", (3, 3)), ("a", "<u2")]))
            return a["v"].reshape(-1, 3).astype(float)
    pts = [list(map(float, l.split()[1:4])) for l in b.decode("ascii", "replace").splitlines()
           if l.strip().startswith("vertex")]
    return np.array(pts)


def outside(hull, pts):
    """Largest signed distance of each point beyond the hull's facets (<= 0: inside)."""
    eq = hull.equations  # n . x + d <= 0 inside, n unit
    return (pts @ eq[:, :3].T + eq[:, 3]).max(axis=1)


def decimate(pts, max_vertices=MAX_VERTICES, offset=False):
    full = ConvexHull(pts)
    hv = pts[full.vertices]
    if len(hv) <= max_vertices:
        sub = hv
    else:
        # Start with the extremes along 13 directions, then greedily the farthest outside.
        dirs = [(1, 0, 0), (0, 1, 0), (0, 0, 1), (1, 1, 0), (1, -1, 0), (1, 0, 1), (1, 0, -1), (0, 1, 1),
                (0, 1, -1), (1, 1, 1), (1, 1, -1), (1, -1, 1), (-1, 1, 1)]
        idx = set()
        for d in dirs:
            s = hv @ np.array(d, float)
            idx.add(int(s.argmax()))
            idx.add(int(s.argmin()))
        idx = sorted(idx)
        while len(idx) < max_vertices:
            h = ConvexHull(hv[idx])
            o = outside(h, hv)
            k = int(o.argmax())
            if o[k] <= 0:
                break
            idx.append(k)
        sub = hv[idx]
    if not offset:
        # Scale about the centroid until every source vertex is inside, plus PAD_M.
        c = sub.mean(axis=0)
        h = ConvexHull(sub)
        n, d = h.equations[:, :3], h.equations[:, 3]
        b = -(d + n @ c)  # distance of each facet from c (> 0)
        ratio = ((pts - c) @ n.T + PAD_M) / b
        s = max(1.0, float(ratio.max()))
        out = c + (sub - c) * s
        hull = ConvexHull(out)
        return out, hull, s, full
    # Move each facet of the subset's hull out by the farthest any point lies beyond it, plus
    # PAD_M (a thin piece grows by that, not by a scale along its length); the vertices are
    # the halfspaces' intersection.
    from scipy.spatial import HalfspaceIntersection
    h = ConvexHull(sub)
    eq = h.equations.copy()
    eq[:, 3] -= np.maximum((pts @ eq[:, :3].T + eq[:, 3]).max(axis=0), 0.0) + PAD_M
    out = HalfspaceIntersection(eq, sub.mean(axis=0)).intersections
    hull = ConvexHull(out)
    out = out[hull.vertices]
    hull = ConvexHull(out)
    return out, hull, 1.0, full


def write_obj(path, pts, hull, header):
    # Only the hull's vertices, renumbered; triangles wound outward.
    keep = sorted(set(hull.simplices.flatten().tolist()))
    ren = {k: i + 1 for i, k in enumerate(keep)}
    c = pts[keep].mean(axis=0)
    L = ["# " + l for l in header]
    L += ["v %.6f %.6f %.6f" % tuple(pts[k]) for k in keep]
    for tri, eq in zip(hull.simplices, hull.equations):
        a, b, cc = pts[tri]
        if np.dot(np.cross(b - a, cc - a), eq[:3]) < 0:
            tri = tri[[0, 2, 1]]
        L.append("f %d %d %d" % tuple(ren[int(t)] for t in tri))
    with open(path, "w") as f:
        f.write("\n".join(L) + "\n")
    return len(keep)


def read_obj(path):
    return np.array([[float(x) for x in l.split()[1:4]] for l in open(path) if l.startswith("v ")])


def our_joint_origins(name):
    import xml.etree.ElementTree as ET
    r = ET.parse(os.path.join(ROOT, "robots", name, "robot.urdf")).getroot()
    out = []
    for j in r.findall("joint"):
        if j.get("name") in ["joint_%d" % i for i in range(1, 7)]:
            o = j.find("origin")
            out.append((tuple(map(float, o.get("xyz").split())), tuple(map(float, o.get("rpy").split()))))
    return out


def visual_of(src, ext):
    """The source's visual mesh of the link whose collision mesh is `src` (same folder layout)."""
    return src.replace("/collision/", "/visual/").rsplit(".", 1)[0] + ext


def mesh_of(b, ext):
    import trimesh
    m = trimesh.load(io.BytesIO(b), file_type=ext.lstrip("."), force="mesh")
    m.merge_vertices()
    return np.asarray(m.vertices, float), np.asarray(m.faces, np.int64)


def decompose(v, f):
    """CoACD pieces of the mesh (v, f): a list of vertex arrays."""
    import coacd
    coacd.set_log_level("error")
    parts = coacd.run_coacd(coacd.Mesh(v, f), threshold=CONCAVITY, max_convex_hull=MAX_PIECES,
                            preprocess_mode="auto", preprocess_resolution=PREPROCESS_RESOLUTION, resolution=1000, mcts_iterations=30, mcts_max_depth=2,
                            mcts_nodes=10, seed=SEED)
    return [np.asarray(p[0], float) for p in parts]


def fill_ratio(v, f):
    """Volume of the closed mesh (v, f) over its convex hull's; None for an open mesh."""
    import trimesh
    m = trimesh.Trimesh(v, f, process=False)
    return float(m.volume / m.convex_hull.volume) if m.is_watertight else None


def least_outside(hulls, pts):
    """For each point: (index of the piece it is least outside of, that distance; <= 0 inside)."""
    o = np.stack([outside(h, pts) for h in hulls], axis=1)
    k = o.argmin(axis=1)
    return k, o[np.arange(len(pts)), k]


def main():
    args = sys.argv[1:]
    check = "--check" in args
    dirs = {"abb": args[args.index("--abb") + 1], "ur": args[args.index("--ur") + 1]}
    bad = 0
    only = args[args.index("--only") + 1].split(",") if "--only" in args else list(ROBOTS)
    for name, spec in ROBOTS.items():
        if name not in only:
            continue
        # The link frames: our joint origins are the source's.
        for i, ((p0, r0), (p1, r1)) in enumerate(zip(spec["joints"], our_joint_origins(name))):
            T0 = rpy_matrix(*r0)
            T1 = rpy_matrix(*r1)
            if np.abs(np.array(p0) - p1).max() > 1e-9 or np.abs(T0 - T1).max() > 1e-9:
                print("%s joint_%d: origin differs from the source's" % (name, i + 1))
                bad += 1
        out_dir = os.path.join(ROOT, "robots", name, "collision")
        os.makedirs(out_dir, exist_ok=True)
        rows = []
        for link, src, xyz, rpy in spec["links"]:
            place = lambda p: p @ rpy_matrix(*rpy).T + np.array(xyz, float)
            cpts = place(stl_vertices(git_bytes(dirs[spec["repo"]], spec["commit"], src)))
            vsrc = visual_of(src, spec["visual_ext"])
            v, f = mesh_of(git_bytes(dirs[spec["repo"]], spec["commit"], vsrc), spec["visual_ext"])
            v = place(v)
            # The visual mesh is the collision mesh's shape: inside its (convex) hull.
            chull = ConvexHull(cpts)
            vin = float(outside(chull, v).max())
            if vin > VISUAL_IN_COLLISION_M:
                print("%s %s: visual mesh reaches %.1f mm outside the published collision mesh" % (
                    name, link, vin * 1000))
                bad += 1
            # How much of its hull the link fills (closed visual meshes only).
            fill = fill_ratio(v, f)
            split = link in spec["decompose"]
            files = sorted(x for x in os.listdir(out_dir) if x.startswith(link + "-") and x.endswith(".obj"))
            src_pts = v if split else cpts
            if check:
                hulls = [ConvexHull(read_obj(os.path.join(out_dir, x))) for x in files]
                _, o = least_outside(hulls, src_pts)
                ok = len(hulls) > 0 and o.max() <= 1e-3
                print("%s %s: %d pieces, %d source vertices, largest outside the pieces %.2e m %s" % (
                    name, link, len(hulls), len(src_pts), max(o.max(), 0.0), "ok" if ok else "FAIL"))
                bad += not ok
                continue
            for x in files:
                os.remove(os.path.join(out_dir, x))
            old = os.path.join(out_dir, link + ".obj")
            if os.path.exists(old):
                os.remove(old)
            if split:
                parts = decompose(v, f)
                hulls = [ConvexHull(p) for p in parts]
                k, _ = least_outside(hulls, v)
                groups = [np.vstack([parts[j], v[k == j]]) for j in range(len(parts))]
                one = ConvexHull(v)
                used = vsrc
            else:
                groups = [cpts]
                one = chull
                used = src
            written = []
            for j, pts in enumerate(groups):
                out, hull, sc, full = decimate(pts, PIECE_MAX_VERTICES if split else MAX_VERTICES, offset=split)
                grow = float(np.max(outside(full, out)))
                path = os.path.join(out_dir, "%s-%d.obj" % (link, j + 1))
                nv = write_obj(path, out, hull, [
                    "printwatt collision piece %d of %d of %s `%s` (link frame, m), by tools/robots/collision_hulls.py"
                    % (j + 1, len(groups), name, link),
                    "source: %s @ %s : %s (%s)" % (spec["url"], spec["commit"], used, spec["licence"].split(" (")[0]),
                    "convex hull of the piece's points, decimated to %d vertices and scaled by %.4f about its centroid"
                    % (len(out), sc),
                    "so that every point is inside (largest outward offset from the piece's hull %.1f mm)"
                    % (grow * 1000)])
                lo, hi = out.min(axis=0), out.max(axis=0)
                written.append((j + 1, nv, sc, grow, hull.volume, lo, hi))
            vol = sum(w[4] for w in written)
            rows.append((link, used, len(src_pts), fill, written, vol / one.volume, vin))
            print("%s %s: fill %s, %s, written %d pieces (%.2f of the hull)" % (
                name, link, "%.2f" % fill if fill else "open mesh", "decomposed" if split else "one hull",
                len(written), vol / one.volume))
            for w in written:
                print("   piece %d: %d vertices, scale %.4f, +%.1f mm, box %s .. %s" % (
                    w[0], w[1], w[2], w[3] * 1000, np.round(w[5], 3), np.round(w[6], 3)), flush=True)
        if not check:
            write_readme(name, spec, rows, out_dir)
    if bad:
        sys.exit("%d check(s) failed" % bad)


def write_readme(name, spec, rows, out_dir):
    L = ["# Collision geometry of `%s`" % name, "",
         "Generated by `tools/robots/collision_hulls.py`; do not edit. Each link is one or a few convex pieces "
         "(`<link>-<k>.obj`), in the link frame of `../robot.urdf` (m), as Wavefront OBJ (vertices and outward "
         "triangles). `tools/robots/make_robots.py` names each piece in its own `<collision>` element.", "",
         "- Source: %s at commit `%s`, the meshes named below (their `<collision>` / `<visual>` origins from `%s` "
         "applied; the two are the same there)." % (spec["url"], spec["commit"], spec["xacro"]),
         "- Licence: %s. The pieces are derived from those meshes; the licence text is `LICENSE` here." % spec["licence"],
         "- Frames: the source's joint origins agree with `../robot.urdf` (checked by the script), so the source's "
         "link frames are ours.",
         "- The source's collision meshes are convex hulls of its visual meshes (every visual vertex lies inside the "
         "published collision hull; the largest excess is in the table). One hull per link would close the "
         "forearm's fork around the wrist, through which the hose passes.",
         "- Decomposed links (%s): an approximate convex decomposition of the visual mesh (CoACD, Wei et al. 2022, "
         "concavity threshold %.2f, at most %d pieces, seed %d; an open mesh is first remeshed closed on a %d-cell "
         "grid); every visual vertex outside all pieces joins the piece it is least outside of." % (
             ", ".join("`%s`" % l for l in spec["decompose"]) or "none", CONCAVITY, MAX_PIECES, SEED,
             PREPROCESS_RESOLUTION),
         "- Other links: one convex hull of the published collision mesh. The fill column says how much of its hull "
         "the link's closed visual mesh fills (open meshes: not computed): a low fill is a housing whose hull is "
         "larger than the housing, conservative.",
         "- Each piece: the convex hull of its points, reduced to a greedy subset of at most %d vertices (each step "
         "the vertex farthest outside), made CONSERVATIVE again: a one-hull link's subset is scaled about its centroid "
         "by the smallest factor that puts every point inside plus %.1f mm; a decomposed link's piece (thin prongs, "
         "which a scale would lengthen by centimetres) has each facet of the subset moved out by the farthest point "
         "beyond it plus %.1f mm, its vertices the intersection of those halfspaces (a few hundred). So the pieces "
         "together contain the source mesh (`--check` verifies within 1 mm); the largest growth over the source's "
         "hull is in the table."
         % (MAX_VERTICES, PAD_M * 1000, PAD_M * 1000)]
    if spec["note"]:
        L.append("- " + spec["note"])
    L += ["", "| Link | Mesh used | Vertices | Visual fill of its hull | Visual outside the published hull (mm) "
          "| Pieces (volume / hull) | Piece: vertices, scale, largest growth (mm), box (m) |",
          "|---|---|---|---|---|---|---|"]
    for link, used, nv, fill, written, wr, vin in rows:
        ps = "<br>".join("%d: %d, %.4f, %.1f, (%.3f, %.3f, %.3f) .. (%.3f, %.3f, %.3f)" % (
            w[0], w[1], w[2], w[3] * 1000, *w[5], *w[6]) for w in written)
        L.append("| `%s` | `%s` | %d | %s | %.1f | %d (%.2f) | %s |" % (
            link, used, nv, "%.2f" % fill if fill else "open mesh", max(vin, 0.0) * 1000, len(written), wr, ps))
    with open(os.path.join(out_dir, "README.md"), "w") as f:
        f.write("\n".join(L) + "\n")


if __name__ == "__main__":
    main()
