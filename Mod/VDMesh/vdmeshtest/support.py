"""What the tests measured: each test adds lines with figure(); tearDownClass prints them together,
so that the figures stand after unittest's verbose output instead of inside it."""
import sys

import FreeCAD

FIGURES = {}


def figure(line, group="default"):
    FIGURES.setdefault(group, []).append(line)
    FreeCAD.Console.PrintMessage("  " + line + "\n")


def print_figures(title, group="default"):
    lines = FIGURES.pop(group, [])
    sys.stdout.write("\n%s figures:\n%s\n" % (title, "\n".join("  " + l for l in lines)))
    sys.stdout.flush()


def add_box_with_hole(doc):
    """A parametric 10 x 10 x 4 box with a diameter-4 hole through it (Part::Cut), as the headless tests mesh it."""
    from FreeCAD import Vector
    box = doc.addObject("Part::Box", "Box")
    box.Length, box.Width, box.Height = 10, 10, 4
    box.Placement.Base = Vector(-5, -5, 0)
    cyl = doc.addObject("Part::Cylinder", "Hole")
    cyl.Radius, cyl.Height = 2, 6
    cyl.Placement.Base = Vector(0, 0, -1)
    cut = doc.addObject("Part::Cut", "BoxWithHole")
    cut.Base, cut.Tool = box, cyl
    doc.recompute()
    return cut
