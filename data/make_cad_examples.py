#!/usr/bin/python3
"""Writes the CAD examples of data/ with Gmsh's OpenCASCADE kernel (Debian: python3-gmsh).

    data/make_cad_examples.py              writes data/plate_slot.step, data/lblock_blocks.step,
                                           data/open_shell.step and data/closed_shell.step
    data/make_cad_examples.py --shapes DIR writes cube, lblock, lblock_blocks (the same L-block
                                           as three glued boxes), cylinder and sphere .step
                                           files into DIR (for bench/cad_vs_gmsh.py)

plate_slot.step: a 4 x 2 x 0.5 plate with a slot 0.6 wide cut from one long side, 1.2 deep,
with a round end; the slot is open on the side, so the solid has genus 0.
lblock_blocks.step: a 2 x 2 x 1 L-block as three unit boxes glued face to face, each solid
with its own copy of the faces it shares (as STEP assemblies are), every face four-sided.
open_shell.step: a unit cube's boundary with one face missing: five faces and no volume, the
input stcweave must refuse ("not a closed solid"); closed_shell.step: all six faces and no
volume, which stcweave sews into a solid (as IGES files, which rarely hold solids, need).
The system python is named on purpose: python3-gmsh installs the module there.
"""
import os
import sys

import gmsh


def plate_slot(occ):
    plate = occ.addBox(0, 0, 0, 4, 2, 0.5)
    width, depth = 0.6, 1.2
    x0 = 2 - width / 2
    # The slot: a box from the side y = 0 up to the centre of its round end, and the end.
    box = occ.addBox(x0, -0.1, -0.1, width, depth - width / 2 + 0.1, 0.7)
    end = occ.addCylinder(2, depth - width / 2, -0.1, 0, 0, 0.7, width / 2)
    slot, _ = occ.fuse([(3, box)], [(3, end)])
    occ.cut([(3, plate)], slot)


def open_shell(occ):
    occ.addBox(0, 0, 0, 1, 1, 1)
    occ.synchronize()
    occ.remove([(3, 1)])
    occ.remove([(2, 6)])


def closed_shell(occ):
    occ.addBox(0, 0, 0, 1, 1, 1)
    occ.synchronize()
    occ.remove([(3, 1)])


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
        for name in ["cube", "lblock", "lblock_blocks", "cylinder", "sphere"]:
            write(os.path.join(sys.argv[2], name + ".step"), shapes, name)
    elif len(sys.argv) == 1:
        here = os.path.dirname(os.path.abspath(__file__))
        write(os.path.join(here, "plate_slot.step"), plate_slot)
        write(os.path.join(here, "open_shell.step"), open_shell)
        write(os.path.join(here, "closed_shell.step"), closed_shell)
        write(os.path.join(here, "lblock_blocks.step"), shapes, "lblock_blocks")
    else:
        print(__doc__, file=sys.stderr)
        sys.exit(1)
    gmsh.finalize()


if __name__ == "__main__":
    main()
