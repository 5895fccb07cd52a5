#!/usr/bin/python3
"""Writes the CAD examples of data/ with Gmsh's OpenCASCADE kernel (Debian: python3-gmsh).

    data/make_cad_examples.py              writes data/plate_slot.step, data/lblock_blocks.step,
                                           data/plate_hole_blocks.step, data/torus_blocks.step,
                                           data/open_shell.step, data/closed_shell.step and
                                           data/cylinder_tilted.step, data/torus_tilted.step,
                                           data/plate_hole_tilted.step,
                                           data/plate_blind_hole.step,
                                           data/plate_two_holes.step,
                                           data/box_cavity.step and
                                           data/hollow_torus.step
    data/make_cad_examples.py --shapes DIR writes the .step files of SHAPES into DIR (for
                                           bench/cad_vs_gmsh.py): cube, lblock, cylinder,
                                           sphere, plate_hole and torus as one solid each, and
                                           each of the last five but the cube also built of
                                           blocks glued face to face (NAME_blocks), every
                                           face of the blocks four-sided; and
                                           plate_blind_hole, plate_two_holes, box_cavity
                                           (as in data/)

plate_slot.step: a 4 x 2 x 0.5 plate with a slot 0.6 wide cut from one long side, 1.2 deep,
with a round end; the slot is open on the side, so the solid has genus 0.
lblock_blocks.step: a 2 x 2 x 1 L-block as three unit boxes glued face to face, each solid
with its own copy of the faces it shares (as STEP assemblies are), every face four-sided.
plate_hole_blocks.step: a 4 x 2 x 0.5 plate with a through-hole of radius 0.5 at its centre
(genus 1), as four blocks cut along the plate's diagonals, so every face has four corners.
torus_blocks.step: a torus (radius 1, tube radius 0.4) as 20 blocks, the tube's section split
as an O-grid and swept in four quarter turns, every face four-sided. (The same two as one
solid each, plate_hole and torus of --shapes, have faces without four corners.)
cylinder_tilted.step: a cylinder of radius 0.5 and height 1 whose axis runs from (0.2, 0.1, 0)
along (1, 2, 2) / 3, not along a coordinate axis (the O-grid split must follow it).
torus_tilted.step: the torus of torus_blocks.step as one solid (one toroidal face), its axis
along (2, -1, 2) / 3 through (0.3, -0.2, 0.5) (the split into blocks must find both).
plate_hole_tilted.step: a 4 x 2 x 0.5 plate with a through-hole of radius 0.4 off its centre
(at (1.3, 0.8)), one solid, turned so that its normal is (1, 2, 2) / 3 and moved by
(0.1, 0.2, 0.3). plate_blind_hole.step: the plate of plate_hole_blocks.step as one solid with
a blind hole instead (radius 0.5, 0.3 deep from the top face; genus 0). plate_two_holes.step:
the same plate as one solid with two through-holes of radius 0.4 at (1.2, 1) and (2.8, 1)
(genus 2; not split into blocks, so its surface is mixed or triangle-split). box_cavity.step:
a 2 x 2 x 2 box with a spherical cavity of radius 0.5 at its centre (two shells, one solid).
hollow_torus.step: a torus (radius 1, tube radius 0.4) with a toroidal cavity (tube radius
0.2) along its core circle: a cavity with a handle (two shells of genus 1, one solid); its
periodic faces are what Gmsh 4.8 may fail to mesh at coarse sizes.
open_shell.step: a unit cube's boundary with one face missing: five faces and no volume, the
input stcweave must refuse ("not a closed solid"); closed_shell.step: all six faces and no
volume, which stcweave sews into a solid (as IGES files, which rarely hold solids, need).
The system python is named on purpose: python3-gmsh installs the module there.
"""
import math
import os
import sys

import gmsh


SHAPES = ["cube", "lblock", "lblock_blocks", "cylinder", "cylinder_blocks", "sphere",
          "sphere_blocks", "plate_hole", "plate_hole_blocks", "torus", "torus_blocks",
          "plate_blind_hole", "plate_two_holes", "box_cavity"]


def plate_slot(occ):
    plate = occ.addBox(0, 0, 0, 4, 2, 0.5)
    width, depth = 0.6, 1.2
    x0 = 2 - width / 2
    # The slot: a box from the side y = 0 up to the centre of its round end, and the end.
    box = occ.addBox(x0, -0.1, -0.1, width, depth - width / 2 + 0.1, 0.7)
    end = occ.addCylinder(2, depth - width / 2, -0.1, 0, 0, 0.7, width / 2)
    slot, _ = occ.fuse([(3, box)], [(3, end)])
    occ.cut([(3, plate)], slot)


def cylinder_tilted(occ):
    occ.addCylinder(0.2, 0.1, 0, 1 / 3, 2 / 3, 2 / 3, 0.5)


def turned_onto(occ, dim_tags, axis, origin):
    """Turns dim_tags (built along z from the origin) so that z goes along the unit axis,
    then moves the origin to origin."""
    turn = (-axis[1], axis[0], 0.0)
    occ.rotate(dim_tags, 0, 0, 0, turn[0], turn[1], turn[2], math.acos(axis[2]))
    occ.translate(dim_tags, *origin)


def torus_tilted(occ):
    turned_onto(occ, [(3, occ.addTorus(0, 0, 0, 1, 0.4))], (2 / 3, -1 / 3, 2 / 3), (0.3, -0.2, 0.5))


def plate_hole_tilted(occ):
    plate = occ.addBox(0, 0, 0, 4, 2, 0.5)
    hole = occ.addCylinder(1.3, 0.8, -0.5, 0, 0, 1.5, 0.4)
    out, _ = occ.cut([(3, plate)], [(3, hole)])
    turned_onto(occ, out, (1 / 3, 2 / 3, 2 / 3), (0.1, 0.2, 0.3))


def plate_blind_hole(occ):
    plate = occ.addBox(0, 0, 0, 4, 2, 0.5)
    hole = occ.addCylinder(2, 1, 0.2, 0, 0, 1, 0.5)
    occ.cut([(3, plate)], [(3, hole)])


def plate_two_holes(occ):
    plate = occ.addBox(0, 0, 0, 4, 2, 0.5)
    left = occ.addCylinder(1.2, 1, -0.5, 0, 0, 1.5, 0.4)
    right = occ.addCylinder(2.8, 1, -0.5, 0, 0, 1.5, 0.4)
    occ.cut([(3, plate)], [(3, left), (3, right)])


def box_cavity(occ):
    box = occ.addBox(0, 0, 0, 2, 2, 2)
    ball = occ.addSphere(1, 1, 1, 0.5)
    occ.cut([(3, box)], [(3, ball)])


def hollow_torus(occ):
    outer = occ.addTorus(0, 0, 0, 1, 0.4)
    inner = occ.addTorus(0, 0, 0, 1, 0.2)
    occ.cut([(3, outer)], [(3, inner)])


def open_shell(occ):
    occ.addBox(0, 0, 0, 1, 1, 1)
    occ.synchronize()
    occ.remove([(3, 1)])
    occ.remove([(2, 6)])


def closed_shell(occ):
    occ.addBox(0, 0, 0, 1, 1, 1)
    occ.synchronize()
    occ.remove([(3, 1)])


def plate_hole(occ):
    """A 4 x 2 x 0.5 plate with a through-hole of radius 0.5 at its centre (genus 1)."""
    plate = occ.addBox(0, 0, 0, 4, 2, 0.5)
    hole = occ.addCylinder(2, 1, -0.5, 0, 0, 1.5, 0.5)
    occ.cut([(3, plate)], [(3, hole)])


def plate_hole_blocks(occ, a=4.0, b=2.0, c=0.5):
    """The same plate as four blocks cut along its diagonals, every face four-sided."""
    cx, cy, radius = a / 2, b / 2, min(a, b) / 4
    centre = occ.addPoint(cx, cy, 0)
    corners, on_hole = [], []
    for x, y in [(0, 0), (a, 0), (a, b), (0, b)]:
        length = math.hypot(x - cx, y - cy)
        corners.append(occ.addPoint(x, y, 0))
        on_hole.append(occ.addPoint(cx + radius * (x - cx) / length,
                                    cy + radius * (y - cy) / length, 0))
    edge = [occ.addLine(corners[k], corners[(k + 1) % 4]) for k in range(4)]
    cut = [occ.addLine(on_hole[k], corners[k]) for k in range(4)]
    arc = [occ.addCircleArc(on_hole[k], centre, on_hole[(k + 1) % 4]) for k in range(4)]
    pieces = []
    for k in range(4):
        loop = occ.addCurveLoop([edge[k], -cut[(k + 1) % 4], -arc[k], cut[k]])
        face = occ.addPlaneSurface([loop])
        pieces += [dt for dt in occ.extrude([(2, face)], 0, 0, c) if dt[0] == 3]
    occ.fragment(pieces[:1], pieces[1:])


def torus_blocks(occ, major=1.0, minor=0.4):
    """A torus as 20 blocks: its section split as an O-grid (square core, four ring
    pieces), swept a quarter turn and copied around the axis; every face four-sided."""
    half, diagonal = minor / 2.5, minor / math.sqrt(2)
    directions = [(1, -1), (1, 1), (-1, 1), (-1, -1)]
    centre = occ.addPoint(major, 0, 0)
    core = [occ.addPoint(major + half * u, 0, half * v) for u, v in directions]
    rim = [occ.addPoint(major + diagonal * u, 0, diagonal * v) for u, v in directions]
    side = [occ.addLine(core[k], core[(k + 1) % 4]) for k in range(4)]
    cut = [occ.addLine(core[k], rim[k]) for k in range(4)]
    arc = [occ.addCircleArc(rim[k], centre, rim[(k + 1) % 4]) for k in range(4)]
    section = [(2, occ.addPlaneSurface([occ.addCurveLoop(side)]))]
    for k in range(4):
        loop = occ.addCurveLoop([side[k], cut[(k + 1) % 4], -arc[k], -cut[k]])
        section.append((2, occ.addPlaneSurface([loop])))
    blocks = [dt for dt in occ.revolve(section, 0, 0, 0, 0, 0, 1, math.pi / 2) if dt[0] == 3]
    first = list(blocks)
    for turn in range(1, 4):
        copy = occ.copy(first)
        occ.rotate(copy, 0, 0, 0, 0, 0, 1, turn * math.pi / 2)
        blocks += copy
    occ.fragment(blocks[:1], blocks[1:])


def cylinder_blocks(occ, radius=0.5, height=1.0):
    """Cylinder as an O-grid of 5 blocks: square core of half side radius/2.5 and four ring
    pieces, extruded; every face four-sided."""
    half, diagonal = radius / 2.5, radius / math.sqrt(2)
    directions = [(1, -1), (1, 1), (-1, 1), (-1, -1)]
    centre = occ.addPoint(0, 0, 0)
    core = [occ.addPoint(half * u, half * v, 0) for u, v in directions]
    rim = [occ.addPoint(diagonal * u, diagonal * v, 0) for u, v in directions]
    side = [occ.addLine(core[k], core[(k + 1) % 4]) for k in range(4)]
    cut = [occ.addLine(core[k], rim[k]) for k in range(4)]
    arc = [occ.addCircleArc(rim[k], centre, rim[(k + 1) % 4]) for k in range(4)]
    section = [(2, occ.addPlaneSurface([occ.addCurveLoop(side)]))]
    for k in range(4):
        section.append((2, occ.addPlaneSurface([occ.addCurveLoop([side[k], cut[(k + 1) % 4], -arc[k], -cut[k]])])))
    blocks = [dt for dt in occ.extrude(section, 0, 0, height) if dt[0] == 3]
    occ.fragment(blocks[:1], blocks[1:])

def sphere_blocks(occ, radius=0.5):
    """Cubed sphere: a core cube of half side radius/2.5 and six blocks, each the sphere cut by
    the pyramid from the centre through a face of the cube; every face four-sided."""
    h, big = radius / 2.5, 2 * radius
    apex = occ.addPoint(0, 0, 0)
    base = [occ.addPoint(big * u, big * v, big) for u, v in [(-1, -1), (1, -1), (1, 1), (-1, 1)]]
    rim = [occ.addLine(base[k], base[(k + 1) % 4]) for k in range(4)]
    spoke = [occ.addLine(apex, base[k]) for k in range(4)]
    faces = [occ.addPlaneSurface([occ.addCurveLoop(rim)])]
    for k in range(4):
        faces.append(occ.addPlaneSurface([occ.addCurveLoop([spoke[k], rim[k], -spoke[(k + 1) % 4]])]))
    pyramid = (3, occ.addVolume([occ.addSurfaceLoop(faces)]))
    # The six directions: +z, then quarter turns about x and y, and the half turn about x.
    turns = [None, (1, 0, 0, 0.5), (1, 0, 0, -0.5), (0, 1, 0, 0.5), (0, 1, 0, -0.5), (1, 0, 0, 1)]
    pieces = []
    for turn in turns:
        p = occ.copy([pyramid])
        # OpenCASCADE's sphere has its poles on z and its seam through +x: turned so that its
        # poles are on x and its seam through -z, the +z patch holds neither.
        ball = occ.addSphere(0, 0, 0, radius)
        occ.rotate([(3, ball)], 0, 0, 0, 0, 1, 0, math.pi / 2)
        if turn:
            occ.rotate(p + [(3, ball)], 0, 0, 0, turn[0], turn[1], turn[2], turn[3] * math.pi)
        out, _ = occ.intersect([(3, ball)], p)
        pieces += out
    occ.remove([pyramid], recursive=True)
    core = occ.addBox(-h, -h, -h, 2 * h, 2 * h, 2 * h)
    pieces, _ = occ.cut(pieces, [(3, core)], removeTool=False)
    occ.fragment([(3, core)], pieces)


def shapes(occ, name):
    if name == "cube":
        occ.addBox(0, 0, 0, 1, 1, 1)
    elif name == "lblock":
        whole = occ.addBox(0, 0, 0, 2, 2, 1)
        corner = occ.addBox(1, 1, 0, 1, 1, 1)
        occ.cut([(3, whole)], [(3, corner)])
    elif name == "lblock_blocks":
        first = occ.addBox(0, 0, 0, 1, 1, 1)
        second = occ.addBox(1, 0, 0, 1, 1, 1)
        third = occ.addBox(0, 1, 0, 1, 1, 1)
        occ.fragment([(3, first)], [(3, second), (3, third)])
    elif name == "cylinder":
        occ.addCylinder(0, 0, 0, 0, 0, 1, 0.5)
    elif name == "sphere":
        occ.addSphere(0, 0, 0, 0.5)
    elif name == "cylinder_blocks":
        cylinder_blocks(occ)
    elif name == "sphere_blocks":
        sphere_blocks(occ)
    elif name == "plate_hole":
        plate_hole(occ)
    elif name == "plate_hole_blocks":
        plate_hole_blocks(occ)
    elif name == "torus":
        occ.addTorus(0, 0, 0, 1, 0.4)
    elif name == "torus_blocks":
        torus_blocks(occ)
    elif name == "plate_blind_hole":
        plate_blind_hole(occ)
    elif name == "plate_two_holes":
        plate_two_holes(occ)
    elif name == "box_cavity":
        box_cavity(occ)


def write(path, build, *args):
    gmsh.clear()
    build(gmsh.model.occ, *args)
    gmsh.model.occ.synchronize()
    gmsh.write(path)
    print("wrote", path, file=sys.stderr)


def main():
    gmsh.initialize(readConfigFiles=False)
    gmsh.option.setNumber("General.Terminal", 0)
    if len(sys.argv) == 3 and sys.argv[1] == "--shapes":
        os.makedirs(sys.argv[2], exist_ok=True)
        for name in SHAPES:
            write(os.path.join(sys.argv[2], name + ".step"), shapes, name)
    elif len(sys.argv) == 1:
        here = os.path.dirname(os.path.abspath(__file__))
        write(os.path.join(here, "plate_slot.step"), plate_slot)
        write(os.path.join(here, "open_shell.step"), open_shell)
        write(os.path.join(here, "closed_shell.step"), closed_shell)
        write(os.path.join(here, "lblock_blocks.step"), shapes, "lblock_blocks")
        write(os.path.join(here, "plate_hole_blocks.step"), plate_hole_blocks)
        write(os.path.join(here, "torus_blocks.step"), torus_blocks)
        write(os.path.join(here, "cylinder_tilted.step"), cylinder_tilted)
        write(os.path.join(here, "torus_tilted.step"), torus_tilted)
        write(os.path.join(here, "plate_hole_tilted.step"), plate_hole_tilted)
        write(os.path.join(here, "plate_blind_hole.step"), plate_blind_hole)
        write(os.path.join(here, "plate_two_holes.step"), plate_two_holes)
        write(os.path.join(here, "box_cavity.step"), box_cavity)
        write(os.path.join(here, "hollow_torus.step"), hollow_torus)
    else:
        print(__doc__, file=sys.stderr)
        sys.exit(1)
    gmsh.finalize()


if __name__ == "__main__":
    main()
