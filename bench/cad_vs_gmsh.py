#!/usr/bin/python3
"""stcweave's CAD route side by side with Gmsh's own all-hex mesh of the same solid.

    bench/cad_vs_gmsh.py [--stcweave build/bin/stcweave] [--out build/cad_vs_gmsh] [--size H ...]

For each of cube (1 x 1 x 1), L-block (2 x 2 x 1 minus a 1 x 1 x 1 quarter; once as one solid,
once as three unit boxes glued face to face), cylinder (radius 0.5, height 1), sphere
(radius 0.5; cylinder and sphere also as blocks: an O-grid of 5, a cubed sphere of 7),
plate with a hole (4 x 2 x 0.5, hole of radius 0.5; one solid, and four blocks
cut along the diagonals), torus (radius 1, tube 0.4; one solid, and 20 blocks of an O-grid
section), the plate with a blind hole instead (radius 0.5, 0.3 deep; genus 0, one solid) and
the plate with two through-holes (radius 0.4; genus 2, one solid, not split into blocks) and
a 2 x 2 x 2 box with a spherical cavity (radius 0.5; two shells, one solid),
written as STEP by data/make_cad_examples.py:
- ours:  stcweave mesh SOLID.step -o ours.vtk --size H  (quads of edge ~H);
- Gmsh:  gmsh SOLID.step -3 with Mesh.SubdivisionAlgorithm 2 (tets split into 4 hexes each)
  and Mesh.MeshSizeMax 2H, Mesh.MeshSizeFromPoints 0: the split halves the tets' edges, so its
  hexes have edges ~H too, and its boundary is the same kind of surface as our triangle-split
  recipe (Gmsh's algorithm-6 triangles at 2H, each split into 3 quads).
Ours runs once per rule set (--rules, default: extended and reliable). The front end splits the
one-solid cylinder, sphere, L-block, plate with a hole and torus into blocks itself
(docs/cad.md, "Splitting into blocks"); --mesh-args --no-cad-split gives the rows without that
split.
Both meshes are certified with `stcweave check` and measured with `stcweave quality` (Verdict
scaled Jacobian); times are wall-clock seconds of the whole command (CAD reading included).
Prints a Markdown table (and writes it to OUT/table.md), whose last column says whether ours
beats Gmsh's (valid, 0 inverted, fewer hexes, higher min and mean scaled Jacobian) and by how
much (hexes as a ratio of Gmsh's, min and mean SJ as differences). Extra arguments after
--mesh-args are passed to `stcweave mesh` (e.g. --mesh-args --cad-recipe triangle-split).
Needs gmsh and python3-gmsh.
"""
import argparse
import json
import os
import subprocess
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
SHAPES = ["cube", "lblock", "lblock_blocks", "cylinder", "cylinder_blocks", "sphere",
          "sphere_blocks", "plate_hole", "plate_hole_blocks", "torus", "torus_blocks",
          "plate_blind_hole", "plate_two_holes", "box_cavity"]


def run(cmd, timeout):
    t0 = time.monotonic()
    try:
        p = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                           timeout=timeout)
        return p.returncode, time.monotonic() - t0, p.stdout, p.stderr
    except subprocess.TimeoutExpired:
        return None, time.monotonic() - t0, "", "timeout"


def measure(stcweave, mesh):
    _, _, out, _ = run([stcweave, "check", mesh, "--json"], 600)
    c = json.loads(out)
    _, _, out, _ = run([stcweave, "quality", mesh, "--json"], 600)
    q = json.loads(out)
    return {"valid": c["valid"], "inverted": c["inverted_hexes"], "hexes": c["hexes"],
            "min_sj": q["scaled_jacobian"]["min"], "mean_sj": q["scaled_jacobian"]["mean"]}


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--stcweave", default=os.path.join(HERE, "..", "build", "bin", "stcweave"))
    ap.add_argument("--out", default=os.path.join(HERE, "..", "build", "cad_vs_gmsh"))
    ap.add_argument("--size", type=float, nargs="+", default=[0.25])
    ap.add_argument("--rules", nargs="+", default=["extended", "reliable"])
    ap.add_argument("--timeout", type=float, default=600)
    ap.add_argument("--shapes", nargs="+", default=SHAPES, choices=SHAPES)
    ap.add_argument("--from", dest="sources", nargs="+", default=[],
                    help="render the table from these results.json files instead of running")
    ap.add_argument("--mesh-args", nargs=argparse.REMAINDER, default=[])
    a = ap.parse_args()
    os.makedirs(a.out, exist_ok=True)
    if a.sources:
        rows = [r for src in a.sources for r in json.load(open(src))]
        rows.sort(key=lambda r: (-r["size"], SHAPES.index(r["shape"]),
                                 a.rules.index(r["rules"]) if r["rules"] in a.rules else 99))
        render(rows, a.out)
        return
    subprocess.run([sys.executable, os.path.join(HERE, "..", "data", "make_cad_examples.py"),
                    "--shapes", a.out], check=True, stdout=subprocess.DEVNULL,
                   stderr=subprocess.DEVNULL)
    rows = []
    for size in a.size:
        for shape in a.shapes:
            step = os.path.join(a.out, shape + ".step")
            tag = f"{shape}_{size:g}"
            gm = os.path.join(a.out, tag + ".gmsh.msh")
            rc, t, _, err = run(["gmsh", step, "-3", "-setnumber", "Mesh.SubdivisionAlgorithm",
                                 "2", "-setnumber", "Mesh.MeshSizeMax", str(2 * size),
                                 "-setnumber", "Mesh.MeshSizeFromPoints", "0", "-nopopup",
                                 "-o", gm], a.timeout)
            gmsh_row = measure(a.stcweave, gm) if rc == 0 else {"error": f"exit {rc}"}
            gmsh_seconds = t
            for rules in a.rules:
                ours = os.path.join(a.out, f"{tag}.{rules}.vtk")
                report = os.path.join(a.out, f"{tag}.{rules}.json")
                rc, t, _, err = run([a.stcweave, "mesh", step, "-o", ours, "--size", str(size),
                                     "--rules", rules, "--report", report, "-q"] + a.mesh_args,
                                    a.timeout)
                row = {"shape": shape, "size": size, "rules": rules}
                if rc == 0 and os.path.exists(ours):
                    r = json.load(open(report))
                    row["recipe"] = r["cad"]["recipe"]
                    row["quads"] = r["cad"]["quads"]
                    row["ours"] = measure(a.stcweave, ours)
                else:
                    last = err.strip().splitlines()[-1] if err.strip() else ""
                    row["recipe"] = "-"
                    row["quads"] = "-"
                    row["ours"] = {"error": f"exit {rc}: {last}"}
                row["ours_seconds"] = t
                row["gmsh"] = gmsh_row
                row["gmsh_seconds"] = gmsh_seconds
                rows.append(row)
                print(json.dumps(row), file=sys.stderr)
    json.dump(rows, open(os.path.join(a.out, "results.json"), "w"), indent=1)
    render(rows, a.out)


def short(error):
    """The table's version of a failure: the exit code and the start of the reason (the whole
    message stays in results.json)."""
    error = error.replace("stcweave: invalid input: component 0: ", "")
    if "no choice of discs" in error:
        return error.split(":")[0] + ": no disc cut of the handle is loop-clean"
    return error if len(error) <= 60 else error[:57] + "..."


def render(rows, out):
    def cells(m):
        if "error" in m:
            return [short(m["error"]), "", "", "", ""]
        return ["yes" if m["valid"] else "NO", str(m["inverted"]), str(m["hexes"]),
                f"{m['min_sj']:.3f}", f"{m['mean_sj']:.3f}"]

    def verdict(ours, gm):
        if "error" in ours:
            return "no: " + ("timeout" if "timeout" in ours["error"] else "refused")
        if "error" in gm:
            return "Gmsh failed"
        wins = [ours["valid"], ours["inverted"] == 0, ours["hexes"] < gm["hexes"],
                ours["min_sj"] > gm["min_sj"], ours["mean_sj"] > gm["mean_sj"]]
        return (("yes" if all(wins) else "no") +
                f" ({ours['hexes'] / gm['hexes']:.2f}x hexes, min {ours['min_sj'] - gm['min_sj']:+.3f},"
                f" mean {ours['mean_sj'] - gm['mean_sj']:+.3f})")

    lines = ["| solid | H | recipe | quads | rules | valid | inverted | hexes | min SJ | mean SJ | s "
             "| Gmsh valid | Gmsh inverted | Gmsh hexes | Gmsh min SJ | Gmsh mean SJ | Gmsh s "
             "| beats Gmsh |",
             "|---|--:|---|--:|---|---|--:|--:|--:|--:|--:|---|--:|--:|--:|--:|--:|---|"]
    for r in rows:
        lines.append("| " + " | ".join(
            [r["shape"], f"{r['size']:g}", r["recipe"], str(r["quads"]), r["rules"]] +
            cells(r["ours"]) +
            [f"{r['ours_seconds']:.2f}"] + cells(r["gmsh"]) + [f"{r['gmsh_seconds']:.2f}"] +
            [verdict(r["ours"], r["gmsh"])]) + " |")
    table = "\n".join(lines) + "\n"
    open(os.path.join(out, "table.md"), "w").write(table)
    print(table)


if __name__ == "__main__":
    main()
