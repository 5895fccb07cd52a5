#!/usr/bin/python3
"""Boundaries of Gmsh's own all-hex meshes, as inputs for acceptance runs (issue 11).

usage: make_gmsh_hex_boundaries.py [OUTDIR]   (default: build/gmsh_hex_boundaries)

For a cube, an L-block, a cylinder and a sphere, each at two mesh sizes, Gmsh meshes the
solid with tetrahedra and splits every tet into four hexes (Mesh.SubdivisionAlgorithm 2),
which is how CAD usually becomes an all-hex mesh. The script writes, per case NAME:
  NAME.msh           Gmsh's hex mesh (MSH 2.2, hexahedra only)
  NAME.boundary.obj  its boundary: the hex faces used once, as quads (outward), nodes compacted
and one summary, gmsh_hex_boundaries.json: per case Gmsh's hex count, boundary quad count and
the minimum and mean scaled Jacobian of Gmsh's hexes (Verdict's corner definition, computed
here: Gmsh 4.8's Python API has no getElementQualities).
Needs python3-gmsh (Debian: apt install python3-gmsh); not needed to build or test.
Deterministic for a given Gmsh version (one thread, fixed options).
"""
import json
import os
import sys

try:
    import gmsh
except ImportError:  # pragma: no cover
    sys.exit("make_gmsh_hex_boundaries.py: the gmsh Python module is missing: apt-get install "
             "python3-gmsh and run with /usr/bin/python3")

# (name, builder, mesh size): sizes chosen so that the coarse cases stay small enough for a
# quick run and the fine ones are about eight times larger.
CASES = [
    ("cube", "cube", 0.5),
    ("cube", "cube", 0.25),
    ("lblock", "lblock", 0.5),
    ("lblock", "lblock", 0.25),
    ("cylinder", "cylinder", 0.5),
    ("cylinder", "cylinder", 0.25),
    ("sphere", "sphere", 0.5),
    ("sphere", "sphere", 0.3),
]

# Faces of a VTK/Gmsh-ordered hex, outward for a positively oriented hex.
HEX_FACES = [(0, 3, 2, 1), (4, 5, 6, 7), (0, 1, 5, 4), (1, 2, 6, 5), (2, 3, 7, 6), (3, 0, 4, 7)]


def build(kind):
    occ = gmsh.model.occ
    if kind == "cube":
        occ.addBox(0, 0, 0, 1, 1, 1)
    elif kind == "lblock":
        a = occ.addBox(0, 0, 0, 2, 2, 1)
        b = occ.addBox(1, 1, 0, 1, 1, 1)
        occ.cut([(3, a)], [(3, b)])
    elif kind == "cylinder":
        occ.addCylinder(0, 0, 0, 0, 0, 2, 1)
    elif kind == "sphere":
        occ.addSphere(0, 0, 0, 1)
    occ.synchronize()


def mesh_case(kind, size):
    gmsh.option.setNumber("General.Terminal", 0)
    gmsh.clear()
    gmsh.option.setNumber("General.NumThreads", 1)
    gmsh.option.setNumber("Mesh.MeshSizeMin", size)
    gmsh.option.setNumber("Mesh.MeshSizeMax", size)
    gmsh.option.setNumber("Mesh.SubdivisionAlgorithm", 2)
    gmsh.option.setNumber("Mesh.Algorithm3D", 1)
    build(kind)
    gmsh.model.mesh.generate(3)
    node_tags, coords, _ = gmsh.model.mesh.getNodes()
    index = {int(t): i for i, t in enumerate(node_tags)}
    points = [tuple(coords[3 * i:3 * i + 3]) for i in range(len(node_tags))]
    types, tags, nodes = gmsh.model.mesh.getElements(3)
    hexes = []
    for t, et, en in zip(types, tags, nodes):
        if t != 5:
            raise SystemExit("Gmsh produced non-hex volume elements (type %d)" % t)
        for k in range(len(et)):
            hexes.append([index[int(n)] for n in en[8 * k:8 * k + 8]])
    return points, hexes, [scaled_jacobian(points, h) for h in hexes]


# Corner k of a hex: the node and its three edge neighbours, ordered so that a positively
# oriented hex has a positive determinant (Verdict's corner table).
CORNERS = [(0, 1, 3, 4), (1, 2, 0, 5), (2, 3, 1, 6), (3, 0, 2, 7),
           (4, 7, 5, 0), (5, 4, 6, 1), (6, 5, 7, 2), (7, 6, 4, 3)]


def scaled_jacobian(points, h):
    """Minimum over the 8 corners of det(unit edge vectors) (Verdict's corner term)."""
    worst = 1.0
    for c in CORNERS:
        o = points[h[c[0]]]
        e = []
        for k in c[1:]:
            p = points[h[k]]
            v = (p[0] - o[0], p[1] - o[1], p[2] - o[2])
            n = (v[0] ** 2 + v[1] ** 2 + v[2] ** 2) ** 0.5
            if n == 0.0:
                return 0.0
            e.append((v[0] / n, v[1] / n, v[2] / n))
        a, b, d = e
        det = (a[0] * (b[1] * d[2] - b[2] * d[1]) - a[1] * (b[0] * d[2] - b[2] * d[0]) +
               a[2] * (b[0] * d[1] - b[1] * d[0]))
        worst = min(worst, det)
    return worst


def boundary_quads(hexes):
    count = {}
    for h in hexes:
        for f in HEX_FACES:
            q = tuple(h[i] for i in f)
            key = tuple(sorted(q))
            entry = count.setdefault(key, [0, q])
            entry[0] += 1
    return [q for n, q in count.values() if n == 1]


def write_msh(path, points, hexes):
    with open(path, "w") as out:
        out.write("$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n%d\n" % len(points))
        for i, p in enumerate(points):
            out.write("%d %.17g %.17g %.17g\n" % (i + 1, p[0], p[1], p[2]))
        out.write("$EndNodes\n$Elements\n%d\n" % len(hexes))
        for i, h in enumerate(hexes):
            out.write("%d 5 2 1 1 %s\n" % (i + 1, " ".join(str(v + 1) for v in h)))
        out.write("$EndElements\n")


def write_obj(path, points, quads):
    used = sorted({v for q in quads for v in q})
    new = {v: i + 1 for i, v in enumerate(used)}
    with open(path, "w") as out:
        for v in used:
            out.write("v %.17g %.17g %.17g\n" % points[v])
        for q in quads:
            out.write("f %s\n" % " ".join(str(new[v]) for v in q))


def main():
    outdir = sys.argv[1] if len(sys.argv) > 1 else os.path.join("build", "gmsh_hex_boundaries")
    os.makedirs(outdir, exist_ok=True)
    gmsh.initialize()
    summary = {}
    sizes = {}
    for name, kind, size in CASES:
        sizes.setdefault(name, []).append(size)
        label = "%s_%s" % (name, "coarse" if len(sizes[name]) == 1 else "fine")
        points, hexes, quality = mesh_case(kind, size)
        quads = boundary_quads(hexes)
        write_msh(os.path.join(outdir, label + ".msh"), points, hexes)
        write_obj(os.path.join(outdir, label + ".boundary.obj"), points, quads)
        summary[label] = {
            "mesh_size": size,
            "gmsh_hexes": len(hexes),
            "boundary_quads": len(quads),
            "gmsh_min_scaled_jacobian": min(quality),
            "gmsh_mean_scaled_jacobian": sum(quality) / len(quality),
            "gmsh_inverted": sum(1 for q in quality if q <= 0.0),
        }
        print("%-16s %6d hexes, %5d boundary quads, min SJ %.3f" %
              (label, len(hexes), len(quads), min(quality)))
    gmsh.finalize()
    with open(os.path.join(outdir, "gmsh_hex_boundaries.json"), "w") as out:
        json.dump(summary, out, indent=1, sort_keys=True)
        out.write("\n")


if __name__ == "__main__":
    main()
