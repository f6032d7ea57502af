"""Second-order meshes in the workbench: 10-node tetrahedra (Abaqus C3D10) into the FemMesh, and the
ElementOrder property / `--order 2`. Part of TestVDMeshApp:
`freecadcmd -t TestVDMeshApp.TestVDMeshSecondOrder -M Mod/VDMesh`.

The node order is checked against FreeCAD's own Abaqus writer (FemMesh.writeABAQUS), which maps
SMESH's order to Abaqus' independently of our code, and the volume against FemMesh.Volume, which
FreeCAD sums for 10-node tetrahedra only.
"""
import os
import shutil
import tempfile
import time
import unittest

import FreeCAD
import Part
from FreeCAD import Vector

from vdmeshwb import engine, femmesh, inpreader, meshobject

from .support import add_box_with_hole, figure, print_figures

# one positive tetrahedron (det(v1-v0, v2-v0, v3-v0) = 6 * 4 > 0) with its mid-edge nodes, numbered
# so that every Abaqus position has a different node id
CORNERS = {11: (0.0, 0.0, 0.0), 12: (2.0, 0.0, 0.0), 13: (0.0, 3.0, 0.0), 14: (0.0, 0.0, 4.0)}
C3D10 = (11, 12, 13, 14, 21, 22, 23, 24, 25, 26)  # mid-edge 01 12 20 03 13 23
EDGES = ((0, 1), (1, 2), (2, 0), (0, 3), (1, 3), (2, 3))


def tet10_deck(path):
    nodes = dict(CORNERS)
    corner_ids = C3D10[:4]
    for k, (i, j) in enumerate(EDGES):
        a, b = nodes[corner_ids[i]], nodes[corner_ids[j]]
        nodes[C3D10[4 + k]] = tuple((a[m] + b[m]) / 2 for m in range(3))
    with open(path, "w") as f:
        f.write("*NODE, NSET=NALL\n")
        for n in sorted(nodes):
            f.write("%d, %r, %r, %r\n" % ((n,) + nodes[n]))
        f.write("*ELEMENT, TYPE=C3D10, ELSET=Solid1\n7, %s,\n%s\n"
                % (", ".join(str(n) for n in C3D10[:8]), ", ".join(str(n) for n in C3D10[8:])))
        f.write("*SURFACE, NAME=Face1, TYPE=ELEMENT\n7, S1\n")
    return nodes


def abaqus_elements(path):
    """{element id: node ids} of every C3D10 in a deck written by FreeCAD."""
    return {e: c for e, c in inpreader.read_inp(path).elements.items() if len(c) == 10}


class TestVDMeshSecondOrder(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.doc = FreeCAD.newDocument("VDMeshOrder2")

    @classmethod
    def tearDownClass(cls):
        FreeCAD.closeDocument(cls.doc.Name)
        print_figures("TestVDMeshSecondOrder", "order2")

    def test_1_tet10_deck_into_femmesh(self):
        d = tempfile.mkdtemp(prefix="vdmesh-tet10-")
        self.addCleanup(shutil.rmtree, d, True)
        deck_path = os.path.join(d, "tet10.inp")
        nodes = tet10_deck(deck_path)
        deck = inpreader.read_inp(deck_path)
        self.assertEqual(deck.elements, {7: C3D10})
        fm, info = femmesh.to_femmesh(deck)
        self.assertEqual(fm.VolumeCount, 1)
        self.assertEqual(len(fm.getElementNodes(7)), 10)
        # FreeCAD sums the volume of 10-node tetrahedra itself: 2 * 3 * 4 / 6
        self.assertAlmostEqual(abs(fm.Volume.Value), 4.0, places=9)
        # FreeCAD's writer turns the FemMesh back into the deck's Abaqus order
        out = os.path.join(d, "freecad.inp")
        fm.writeABAQUS(out, 1, False)
        self.assertEqual(abaqus_elements(out), {7: C3D10})
        # our writer (export from a FemMesh alone) does too
        ours = inpreader.read_inp(meshobject.write_inp_from_femmesh(fm, os.path.join(d, "ours.inp")))
        self.assertEqual(ours.elements, {7: C3D10})
        # with the deck's face set: the same side of the element, and the face's nodes mid-edge ones too
        self.assertEqual(ours.surfaces, {"Face1": [(7, 0)]})
        self.assertEqual(ours.nsets["Face1_Nodes"], [11, 12, 13, 21, 22, 23])
        # the face element of Face1 (S1: corners 0 1 2, normal out of the tetrahedron, i.e. -z) is a
        # 6-node triangle whose mid-edge nodes sit between its corners
        groups = femmesh.group_ids(fm)
        (face,) = fm.getGroupElements(groups["Face1_Faces"])
        tri = fm.getElementNodes(face)
        self.assertEqual(len(tri), 6)
        p = [Vector(*nodes[n]) for n in tri]
        self.assertLess((p[1] - p[0]).cross(p[2] - p[0]).z, 0)
        for m in range(3):
            mid = (p[m] + p[(m + 1) % 3]) * 0.5
            self.assertLess((p[3 + m] - mid).Length, 1e-12)
        self.assertEqual(sorted(fm.getGroupElements(groups["Face1_Nodes"])), [11, 12, 13, 21, 22, 23])
        figure("hand-written C3D10 deck: FemMesh volume %.6g (exact 4), FreeCAD's writeABAQUS and ours give "
               "back the deck's node order, Face1 is a 6-node triangle" % abs(fm.Volume.Value), "order2")

    def test_2_element_order_property(self):
        """The part is meshed with ElementOrder 2nd (vdmesh --order 2), then 1st on recompute."""
        usage = engine._run([engine.find_binary(), "mesh", "--help"])
        self.assertIn("--order", usage.stdout + usage.stderr, "%s has no --order option" % engine.find_binary())
        cut = add_box_with_hole(self.doc)
        t = time.time()
        obj, info, report, text = meshobject.create_mesh(cut, engine.Parameters(size=2.0, order=2))
        elapsed = time.time() - t
        self.assertEqual(obj.ElementOrder, "2nd")
        self.assertEqual(info["nodes_per_tetrahedron"], 10)
        fm = obj.FemMesh
        self.assertGreater(fm.VolumeCount, 0)
        self.assertTrue(all(len(fm.getElementNodes(e)) == 10 for e in fm.Volumes))
        # FemMesh's own volume of the 10-node tetrahedra against the part's
        vol = abs(fm.Volume.Value)
        err = abs(vol - cut.Shape.Volume) / cut.Shape.Volume
        self.assertLess(err, 0.005)
        # the mid-edge nodes of the hole's face lie on the cylinder (vdmesh puts them on the CAD face)
        groups = femmesh.group_ids(fm)
        hole = [j for j, f in enumerate(cut.Shape.Faces, 1) if f.Surface.__class__.__name__ == "Cylinder"]
        self.assertEqual(len(hole), 1)
        nodes = fm.Nodes
        worst = 0.0
        for e in fm.getGroupElements(groups["Face%d_Faces" % hole[0]]):
            tri = fm.getElementNodes(e)
            self.assertEqual(len(tri), 6)
            for n in tri[3:]:
                p = nodes[n]
                worst = max(worst, abs((p.x ** 2 + p.y ** 2) ** 0.5 - 2.0))
        self.assertLess(worst, 1e-6)
        # every tetrahedron keeps FemMesh's orientation
        _, negative, count = femmesh.tet_volumes(fm)
        self.assertEqual(negative, count)
        figure("box with hole, size 2, 2nd order: %d nodes, %d 10-node tetrahedra (%.1f s); FemMesh volume %.6g, "
               "FreeCAD %.6g (%.4f %%); hole's mid-edge nodes off the cylinder by at most %.2g"
               % (fm.NodeCount, fm.VolumeCount, elapsed, vol, cut.Shape.Volume, 100 * err, worst), "order2")
        obj.ElementOrder = "1st"
        self.doc.recompute()
        self.assertNotIn("Invalid", obj.State)
        self.assertTrue(all(len(obj.FemMesh.getElementNodes(e)) == 4 for e in obj.FemMesh.Volumes))
        figure("  recompute with ElementOrder 1st: %d 4-node tetrahedra" % obj.FemMesh.VolumeCount, "order2")
