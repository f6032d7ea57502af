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
