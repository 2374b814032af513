#!/usr/bin/env python3
"""Compute the shipped arms' collision hulls once, from the published collision meshes.

    python3 tools/robots/collision_hulls.py --abb ABB_GIT_DIR --ur UR_GIT_DIR          # write
    python3 tools/robots/collision_hulls.py --abb ABB_GIT_DIR --ur UR_GIT_DIR --check  # verify only

ABB_GIT_DIR / UR_GIT_DIR: git directories (a clone or a bare mirror) of
https://github.com/ros-industrial/abb_experimental and
https://github.com/UniversalRobots/Universal_Robots_ROS2_Description; the files are read at the
pinned commits below with `git show`, so nothing else of the clone matters.

For every link: the source mesh's vertices, placed in the link frame of printwatt's URDF by the
source's `<collision><origin>` (and, for the UR10e base, the fixed base_link -> base_link_inertia
turn), then their convex hull (scipy), then decimated to at most MAX_VERTICES vertices while
staying CONSERVATIVE: the hull of a greedy subset of the hull's vertices (each step adds the
vertex farthest outside), then scaled about its centroid by the smallest factor that puts every
source vertex inside (plus 0.1 mm). So the written hull contains the source mesh; how much larger
it is (the scale factor, the largest outward offset) is printed and written to the README.

The link frames: the joint origins of robots/<name>/robot.urdf are compared with the source's
(SOURCE_JOINTS below, transcribed from the source xacro / yaml at the pinned commit); they must
agree to 1e-9 m / rad (for the UR10e our joint_1 origin folds base_link -> base_link_inertia,
yaw pi, into it, so link_1.. are the source's shoulder_link.. frames).

Writes robots/<name>/collision/<link>.obj (vertices and triangles of the decimated hull, m, link
frame). tools/robots/make_robots.py adds the <collision> elements that name them.
Needs numpy and scipy.
"""
import math
import os
import struct
import subprocess
import sys

import numpy as np
from scipy.spatial import ConvexHull

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
MAX_VERTICES = 64
PAD_M = 1e-4

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
        repo="ur", url=UR_URL, commit=UR_COMMIT,
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


def decimate(pts):
    full = ConvexHull(pts)
    hv = pts[full.vertices]
    if len(hv) <= MAX_VERTICES:
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
        while len(idx) < MAX_VERTICES:
            h = ConvexHull(hv[idx])
            o = outside(h, hv)
            k = int(o.argmax())
            if o[k] <= 0:
                break
            idx.append(k)
        sub = hv[idx]
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


def main():
    args = sys.argv[1:]
    check = "--check" in args
    dirs = {"abb": args[args.index("--abb") + 1], "ur": args[args.index("--ur") + 1]}
    bad = 0
    for name, spec in ROBOTS.items():
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
            raw = stl_vertices(git_bytes(dirs[spec["repo"]], spec["commit"], src))
            pts = raw @ rpy_matrix(*rpy).T + np.array(xyz, float)
            path = os.path.join(out_dir, link + ".obj")
            if check:
                got = read_obj(path)
                o = outside(ConvexHull(got), pts).max()
                ok = o <= 1e-3
                print("%s %s: %d source vertices, largest outside the hull %.2e m %s" % (
                    name, link, len(pts), max(o, 0.0), "ok" if ok else "FAIL"))
                bad += not ok
                continue
            out, hull, s, full = decimate(pts)
            grow = float(np.max(outside(full, out)))
            nv = write_obj(path, out, hull, [
                "printwatt collision hull of %s `%s` (link frame, m), by tools/robots/collision_hulls.py" % (name, link),
                "source: %s @ %s : %s (%s)" % (spec["url"], spec["commit"], src, spec["licence"].split(" (")[0]),
                "convex hull of the source's vertices, decimated to %d vertices and scaled by %.4f about its centroid"
                % (len(out), s),
                "so that every source vertex is inside (largest outward offset from the source hull %.1f mm)"
                % (grow * 1000)])
            lo, hi = pts.min(axis=0), pts.max(axis=0)
            rows.append((link, src, len(raw), len(full.vertices), nv, s, grow, lo, hi))
            print("%s %s: %d source vertices, hull %d -> %d, scale %.4f, +%.1f mm, bbox %s .. %s" % (
                name, link, len(raw), len(full.vertices), nv, s, grow * 1000, np.round(lo, 3), np.round(hi, 3)))
        if not check:
            write_readme(name, spec, rows, out_dir)
    if bad:
        sys.exit("%d check(s) failed" % bad)


def write_readme(name, spec, rows, out_dir):
    L = ["# Collision hulls of `%s`" % name, "",
         "Generated by `tools/robots/collision_hulls.py`; do not edit. One convex hull per link, in the link frame "
         "of `../robot.urdf` (m), as Wavefront OBJ (vertices and outward triangles). `tools/robots/make_robots.py` "
         "names them in the URDF's `<collision>` elements.", "",
         "- Source: %s at commit `%s`, the collision meshes named below (the source's `<collision>` origins from "
         "`%s` applied)." % (spec["url"], spec["commit"], spec["xacro"]),
         "- Licence: %s. The hulls are derived from those meshes; the licence text is `LICENSE` here." % spec["licence"],
         "- Frames: the source's joint origins agree with `../robot.urdf` (checked by the script), so the source's "
         "link frames are ours.",
         "- Decimation: convex hull of the mesh's vertices (scipy), at most %d vertices (a greedy subset, each step "
         "the vertex farthest outside), then scaled about its centroid by the smallest factor that puts every source "
         "vertex inside plus %.1f mm: conservative, each hull contains its source mesh (`--check` verifies within "
         "1 mm)." % (MAX_VERTICES, PAD_M * 1000)]
    if spec["note"]:
        L.append("- " + spec["note"])
    L += ["", "| Link | Source file | Source vertices | Hull vertices | Written | Scale | Largest growth (mm) | "
          "Bounding box (m) |", "|---|---|---|---|---|---|---|---|"]
    for link, src, nraw, nfull, nv, s, grow, lo, hi in rows:
        L.append("| `%s` | `%s` | %d | %d | %d | %.4f | %.1f | (%.3f, %.3f, %.3f) .. (%.3f, %.3f, %.3f) |" % (
            link, src, nraw, nfull, nv, s, grow * 1000, *lo, *hi))
    with open(os.path.join(out_dir, "README.md"), "w") as f:
        f.write("\n".join(L) + "\n")


if __name__ == "__main__":
    main()
