#!/usr/bin/python3
"""Quality table of the default pipeline (issue 11): hexes, inverted, min / mean scaled Jacobian.

usage: quality_table.py OUTDIR [--bin PATH] [--gmsh DIR] [--timeout S] [--only SUBSTR]
                        [-- EXTRA stcweave mesh ARGS...]

Runs `stcweave mesh INPUT -o OUTDIR/NAME.vtk --report OUTDIR/NAME.json EXTRA...` on
  - every distinct genus-0, loop-clean surface of ../shared/data listed in CORPUS below (a hex
    mesh and its .boundary.obj, and a _tf_ surface and its reference mesh, counted once), read
    in place (never copied), and
  - with --gmsh DIR, every NAME.boundary.obj that tests/data/make_gmsh_hex_boundaries.py wrote
    into DIR (Gmsh's own figures from DIR/gmsh_hex_boundaries.json are added to the row),
then checks each output with the independent checker ../shared/reference/verify_hex.py
(validity, boundary, corner scaled Jacobian) and prints one Markdown table: our report's figures
(scaled Jacobian with Verdict's centre term), the checker's (8 corners), pillow decision, the
shape phase's min before / after and the seconds. Exit 0 (the reader judges); a run that
times out or fails is a row saying so.
"""
import json
import os
import subprocess
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
DATA = os.path.join(ROOT, "..", "shared", "data")
CHECKER = os.path.join(ROOT, "..", "shared", "reference", "verify_hex.py")

# Distinct genus-0 loop-clean surfaces of the shared corpus (docs/pillowing.md, "Measured").
CORPUS = [
    "gmsh/cube_a6_trisubdiv_coarse.obj",
    "gmsh/cube_tf_coarse.obj",
    "gmsh/cube_tf_medium.obj",
    "gmsh/cylinder_a6_trisubdiv_coarse.obj",
    "gmsh/cylinder_tf_coarse.obj",
    "gmsh/cylinder_tf_medium.obj",
    "gmsh/lblock_a6_trisubdiv_coarse.obj",
    "gmsh/lblock_tf_coarse.obj",
    "gmsh/lblock_tf_medium.obj",
    "gmsh/sphere_a6_trisubdiv_coarse.obj",
    "gmsh/sphere_tf_coarse.obj",
    "gmsh/sphere_tf_medium.obj",
    "real/gmsh-quad/box_c3.boundary.obj",
    "real/hexalab/ecm2017_cylinder_mixed_w_torsion.boundary.obj",
    "real/hexalab/selpad2019_Chamfer_L0.boundary.obj",
    "real/hexalab/selpad2019_Column.boundary.obj",
    "real/hexalab/smf2019_hex_cylinder.boundary.obj",
    "real/hexalab/smf2019_hex_ellipsoid_coarse.boundary.obj",
    "real/hexalab/srf2012_ellipsoid-A.boundary.obj",
    "real/hexalab/srf2012_fandisk.boundary.obj",
    "real/hexalab/svd2016_Dolphin_1.boundary.obj",
    "real/mesquite/hex3Dpart.boundary.obj",
    "real/mesquite/hexes_4by2by2.boundary.obj",
    "real/mesquite/pave2.e.boundary.obj",
    "real/mfem/fichera.boundary.obj",
]


def fmt(x):
    return "-" if x is None else "%.3f" % x


def main():
    args = sys.argv[1:]
    extra = []
    if "--" in args:
        extra = args[args.index("--") + 1:]
        args = args[: args.index("--")]
    if not args:
        print(__doc__)
        sys.exit(1)
    out = args[0]
    binary = os.path.join(ROOT, "build", "bin", "stcweave")
    gmsh_dir = None
    timeout = 600.0
    only = None
    i = 1
    while i < len(args):
        if args[i] == "--bin":
            binary = args[i + 1]
        elif args[i] == "--gmsh":
            gmsh_dir = args[i + 1]
        elif args[i] == "--timeout":
            timeout = float(args[i + 1])
        elif args[i] == "--only":
            only = args[i + 1]
        else:
            print("unknown argument " + args[i])
            sys.exit(1)
        i += 2
    os.makedirs(out, exist_ok=True)
    inputs = []
    if os.path.isdir(DATA):
        inputs += [(p, os.path.join(DATA, p), None) for p in CORPUS]
    if gmsh_dir:
        with open(os.path.join(gmsh_dir, "gmsh_hex_boundaries.json")) as f:
            figures = json.load(f)
        for name in sorted(figures):
            inputs.append(("gmsh-hex/" + name, os.path.join(gmsh_dir, name + ".boundary.obj"),
                           figures[name]))
    if only:
        inputs = [x for x in inputs if only in x[0]]
    print("| input | quads | hexes | inverted | min / mean SJ | checker: valid, inverted, "
          "min / mean corner SJ | pillow | shape min untangled → after | seconds | Gmsh |")
    print("|---|--:|--:|--:|---|---|---|---|--:|---|")
    for label, path, gmsh in inputs:
        name = label.replace("/", "__")
        vtk = os.path.join(out, name + ".vtk")
        rep = os.path.join(out, name + ".json")
        for stale in (vtk, rep):
            if os.path.exists(stale):
                os.remove(stale)
        start = time.time()
        try:
            run = subprocess.run([binary, "mesh", path, "-o", vtk, "--report", rep] + extra,
                                 capture_output=True, text=True, timeout=timeout)
            rc = run.returncode
        except subprocess.TimeoutExpired:
            rc = None
        seconds = time.time() - start
        gm = "-"
        if gmsh:
            gm = "%d, %s / %s" % (gmsh["gmsh_hexes"], fmt(gmsh["gmsh_min_scaled_jacobian"]),
                                  fmt(gmsh["gmsh_mean_scaled_jacobian"]))
        if rc is None or not os.path.exists(rep):
            why = "timeout" if rc is None else "exit %s" % rc
            print("| %s | | | | %s | | | | %.1f | %s |" % (label, why, seconds, gm))
            sys.stdout.flush()
            continue
        with open(rep) as f:
            r = json.load(f)
        q = r.get("quality", {})
        pos = r.get("position", {})
        shape = pos.get("shape", {})
        pil = r.get("pillow", {})
        check = {}
        if os.path.exists(vtk):
            c = subprocess.run(["python3", CHECKER, path, vtk], capture_output=True, text=True)
            try:
                check = json.loads(c.stdout.strip().splitlines()[-1])
            except (ValueError, IndexError):
                check = {}
        print("| %s | %s | %s | %s | %s / %s | %s, %s, %s / %s | %s | %s → %s | %.1f | %s |" % (
            label, r.get("quads"), r.get("hexes"), q.get("inverted"),
            fmt(q.get("min_scaled_jacobian")), fmt(q.get("mean_scaled_jacobian")),
            "yes" if check.get("valid") and check.get("boundary_matches") else "NO",
            check.get("inverted"), fmt(check.get("min_sj")), fmt(check.get("mean_sj")),
            pil.get("shells_pillowed", "-") if pil.get("applied") else "no",
            fmt(shape.get("min_scaled_jacobian_before")), fmt(shape.get("min_scaled_jacobian_after")),
            seconds, gm))
        sys.stdout.flush()


if __name__ == "__main__":
    main()
