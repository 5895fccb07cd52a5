#!/usr/bin/python3
"""Whole pipeline against Gmsh on the same structured solids, side by side in one run.

For each solid (cube, L-block, O-grid cylinder) this script builds the CAD model with Gmsh's
Python API (Debian's python3-gmsh; run it with /usr/bin/python3), meshes it with Gmsh's
transfinite (block-structured) all-hex recipe and times that, takes the boundary quads of
Gmsh's hex mesh as our input surface (OBJ), then runs `stcweave mesh` on that surface and
reads the seconds per stage from its report. Gmsh's time includes meshing the CAD curves
and surfaces, ours starts from the quad surface.

Usage: /usr/bin/python3 bench/gmsh_compare.py [--stcweave build/bin/stcweave] [--out DIR]
       [--n N] [--only cube,lblock,cylinder] [--rules extended]
N is the number of cells along the cube's edge (59 gives the issue's 20,886-quad,
205,379-hex cube); the L-block and the cylinder use sizes that give about the same number of
quads. Prints a Markdown table; writes DIR/gmsh_compare.json.
"""

import argparse
import json
import math
import os
import subprocess
import sys
import time

try:
    import gmsh
except ImportError:  # pragma: no cover
    sys.exit("gmsh_compare.py: the gmsh Python module is missing: apt-get install python3-gmsh "
             "and run with /usr/bin/python3")


def transfinite_all(n_of_curve):
    """Makes every curve, surface and volume of the model transfinite and recombined."""
    for dim, tag in gmsh.model.getEntities(1):
        gmsh.model.mesh.setTransfiniteCurve(tag, n_of_curve(tag) + 1)
    for dim, tag in gmsh.model.getEntities(2):
        gmsh.model.mesh.setTransfiniteSurface(tag)
        gmsh.model.mesh.setRecombine(2, tag)
    for dim, tag in gmsh.model.getEntities(3):
        gmsh.model.mesh.setTransfiniteVolume(tag)


def curve_length(tag):
    lo = gmsh.model.getParametrizationBounds(1, tag)
    pts = [gmsh.model.getValue(1, tag, [lo[0][0] + (lo[1][0] - lo[0][0]) * k / 16.0])
           for k in range(17)]
    return sum(math.dist(pts[k][0:3] if len(pts[k]) >= 3 else pts[k], pts[k + 1][0:3])
               for k in range(16))


def build_cube(n):
    gmsh.model.occ.addBox(0, 0, 0, 1, 1, 1)
    gmsh.model.occ.synchronize()
    transfinite_all(lambda tag: n)


def build_lblock(n):
    # An L of three unit blocks (2 x 2 minus one quarter) extruded by 1: fragments make the
    # blocks share faces, each block is transfinite with n cells per unit length.
    boxes = [gmsh.model.occ.addBox(x, y, 0, 1, 1, 1) for x, y in ((0, 0), (1, 0), (0, 1))]
    gmsh.model.occ.fragment([(3, boxes[0])], [(3, b) for b in boxes[1:]])
    gmsh.model.occ.synchronize()
    transfinite_all(lambda tag: n)


def build_cylinder(n):
    # The O-grid: a centre square of side 2a inside a circle of radius 1, four ring blocks,
    # extruded along z by height 2 (built-in kernel, so the blocks are explicit).
    geo = gmsh.model.geo
    a = 0.5
    centre = geo.addPoint(0, 0, 0)
    sq = [geo.addPoint(a * c, a * s, 0) for c, s in ((1, 1), (-1, 1), (-1, -1), (1, -1))]
    r = 1.0 / math.sqrt(2.0)
    ci = [geo.addPoint(r * c, r * s, 0) for c, s in ((1, 1), (-1, 1), (-1, -1), (1, -1))]
    inner = [geo.addLine(sq[k], sq[(k + 1) % 4]) for k in range(4)]
    arcs = [geo.addCircleArc(ci[k], centre, ci[(k + 1) % 4]) for k in range(4)]
    spokes = [geo.addLine(sq[k], ci[k]) for k in range(4)]
    surfaces = [geo.addPlaneSurface([geo.addCurveLoop(inner)])]
    for k in range(4):
        loop = geo.addCurveLoop([inner[k], spokes[(k + 1) % 4], -arcs[k], -spokes[k]])
        surfaces.append(geo.addPlaneSurface([loop]))
    n_ring = max(1, round(n * 0.5))
    for c in inner + arcs:
        geo.mesh.setTransfiniteCurve(c, n + 1)
    for c in spokes:
        geo.mesh.setTransfiniteCurve(c, n_ring + 1)
    for s in surfaces:
        geo.mesh.setTransfiniteSurface(s)
        geo.mesh.setRecombine(2, s)
    geo.extrude([(2, s) for s in surfaces], 0, 0, 2.0, numElements=[2 * n], recombine=True)
    geo.synchronize()


SOLIDS = {
    # name: (builder, n from the cube's n so that the quad counts are alike)
    "cube": (build_cube, lambda n: n),
    "lblock": (build_lblock, lambda n: max(2, round(n * 0.62))),
    "cylinder": (build_cylinder, lambda n: max(2, round(n * 0.75))),
}


def gmsh_structured(name, n, obj_path):
    """Meshes the solid with Gmsh; returns (seconds, hexes, quads) and writes the boundary."""
    gmsh.initialize()
    gmsh.option.setNumber("General.Terminal", 0)
    gmsh.model.add(name)
    builder, scale = SOLIDS[name]
    start = time.perf_counter()
    builder(scale(n))
    gmsh.model.mesh.generate(3)
    seconds = time.perf_counter() - start
    hexes = []
    for etype, _, nodes in zip(*gmsh.model.mesh.getElements(3)):
        if etype == 5:  # 8-node hexahedron
            hexes = [tuple(nodes[k:k + 8]) for k in range(0, len(nodes), 8)]
    tags, coords, _ = gmsh.model.mesh.getNodes()
    gmsh.finalize()
    # The boundary: hex faces used once (VTK/Gmsh order, outward normals).
    faces = ((0, 3, 2, 1), (4, 5, 6, 7), (0, 1, 5, 4), (1, 2, 6, 5), (2, 3, 7, 6), (3, 0, 4, 7))
    count = {}
    for h in hexes:
        for f in faces:
            q = tuple(int(h[i]) for i in f)
            key = tuple(sorted(q))
            count[key] = (count.get(key, (0, q))[0] + 1, q)
    boundary = [q for c, q in count.values() if c == 1]
    used = sorted({v for q in boundary for v in q})
    index = {v: k + 1 for k, v in enumerate(used)}
    position = {int(t): (coords[3 * k], coords[3 * k + 1], coords[3 * k + 2])
                for k, t in enumerate(tags)}
    with open(obj_path, "w") as out:
        out.write(f"# boundary of Gmsh's transfinite hex mesh of {name} (bench/gmsh_compare.py)\n")
        for v in used:
            x, y, z = position[v]
            out.write(f"v {x!r} {y!r} {z!r}\n")
        for q in boundary:
            out.write("f " + " ".join(str(index[v]) for v in q) + "\n")
    return seconds, len(hexes), len(boundary)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--stcweave", default="build/bin/stcweave")
    ap.add_argument("--out", default="build/gmsh-compare")
    ap.add_argument("--n", type=int, default=59)
    ap.add_argument("--only", default="cube,lblock,cylinder")
    ap.add_argument("--rules", default="extended")
    ap.add_argument("--timeout", type=float, default=600.0)
    args = ap.parse_args()
    os.makedirs(args.out, exist_ok=True)
    rows = []
    for name in args.only.split(","):
        if name not in SOLIDS:
            sys.exit(f"gmsh_compare.py: unknown solid {name!r} (known: {', '.join(SOLIDS)})")
        obj = os.path.join(args.out, f"{name}_tf_{args.n}.obj")
        g_seconds, g_hexes, quads = gmsh_structured(name, args.n, obj)
        report = os.path.join(args.out, f"{name}_tf_{args.n}.report.json")
        cmd = [args.stcweave, "mesh", obj, "-o", os.path.join(args.out, f"{name}_tf_{args.n}.vtk"),
               "--report", report, "-q", "--rules", args.rules]
        start = time.perf_counter()
        try:
            run = subprocess.run(cmd, timeout=args.timeout, capture_output=True, text=True)
            status = "ok" if run.returncode == 0 else f"exit {run.returncode}: {run.stderr.strip()[:80]}"
        except subprocess.TimeoutExpired:
            status = f"timeout {args.timeout:.0f} s"
        wall = time.perf_counter() - start
        row = {"solid": name, "quads": quads, "gmsh_hexes": g_hexes, "gmsh_seconds": g_seconds,
               "status": status, "wall_seconds": wall}
        if os.path.exists(report) and status == "ok":
            with open(report) as f:
                r = json.load(f)
            row.update(hexes=r.get("hexes"), seconds=r.get("seconds", {}),
                       inverted=r.get("quality", {}).get("inverted"),
                       min_sj=r.get("quality", {}).get("min_scaled_jacobian"))
        rows.append(row)
        print(f"gmsh_compare.py: {name}: {quads} quads, {status}", file=sys.stderr)
    with open(os.path.join(args.out, "gmsh_compare.json"), "w") as f:
        json.dump(rows, f, indent=1, sort_keys=True)
    print(f"| solid | quads | Gmsh hexes | Gmsh s | our hexes | weave s | position s | total s | "
          f"wall s | total / Gmsh | inverted | min SJ |")
    print("|---|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|")
    for r in rows:
        s = r.get("seconds", {})
        total = s.get("total")
        ratio = f"{total / r['gmsh_seconds']:.1f}x" if total else r["status"]
        print(f"| {r['solid']} | {r['quads']} | {r['gmsh_hexes']} | {r['gmsh_seconds']:.2f} | "
              f"{r.get('hexes', '–')} | {s.get('weave', float('nan')):.2f} | "
              f"{s.get('position', float('nan')):.2f} | {total if total else float('nan'):.2f} | "
              f"{r['wall_seconds']:.2f} | {ratio} | {r.get('inverted', '–')} | "
              f"{format(r['min_sj'], '.3f') if r.get('min_sj') is not None else '–'} |")


if __name__ == "__main__":
    main()
