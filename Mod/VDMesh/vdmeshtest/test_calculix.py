"""CalculiX through FreeCAD's FEM solver machinery on a vdmesh mesh, against the same analysis on
FreeCAD's own Gmsh mesh (calculix_case.py: a steel / aluminium cantilever of two solids with a hole,
one material per solid, fixed face, pressure). Part of TestVDMeshApp:
`freecadcmd -t TestVDMeshApp.TestVDMeshCalculix -M Mod/VDMesh`.

Both meshes are second order (10-node tetrahedra): linear tetrahedra in bending converge too slowly
to agree within 2 % at sizes a test can afford (tests/freecad/bench_calculix.py, README). The sizes
are ones at which each mesher's result agrees with its own finer meshes (README, "FreeCAD workbench").

Asserted: the largest displacement (0.43 % apart at these sizes). The von Mises stress at single points
is printed, not asserted: neither mesher's value has converged at affordable sizes (at P_alu Gmsh goes
2.204 -> 2.391 and vdmesh 2.301 -> 2.472 from the coarser to the finer size, 8 % each), so a 2 % bound
on it would measure the reference's discretisation error, not vdmesh.
"""
import os
import re
import unittest

import FreeCAD

from vdmeshwb import engine, femmesh, meshobject

from . import calculix_case as case
from .support import figure, print_figures

VDMESH_SIZE = 4.0
GMSH_SIZE = 2.5
AGREEMENT = 0.02


def material_element_counts(inp_path):
    """{material object name: number of elements of its element set} in the deck FreeCAD wrote."""
    with open(inp_path) as f:
        text = f.read()
    counts = {}
    for elset, material in re.findall(r"\*SOLID SECTION,\s*ELSET=(\w+),\s*MATERIAL=(\w+)", text, re.I):
        block = re.search(r"\*ELSET,\s*ELSET=%s\s*\n(.*?)(?=\n\*)" % re.escape(elset), text, re.S | re.I)
        counts[material] = len([x for x in re.split(r"[,\s]+", block.group(1)) if x.strip()]) if block else 0
    return counts


def loaded_area(inp_path, fm):
    """The area of the element faces the first *DLOAD of FreeCAD's CalculiX deck loads (their
    corners: CalculiX's face k of a tetrahedron, FemMesh's first two corners swapped)."""
    with open(inp_path) as f:
        text = f.read()
    faces = re.findall(r"^(\d+),\s*P(\d),", text.split("*DLOAD", 1)[1], re.M)
    corners_of_face = {1: (0, 1, 2), 2: (0, 3, 1), 3: (1, 3, 2), 4: (2, 3, 0)}
    area = 0.0
    for element, k in faces:
        c = fm.getElementNodes(int(element))
        c = [c[1], c[0], c[2], c[3]]
        a, b, d = (fm.Nodes[c[i]] for i in corners_of_face[int(k)])
        area += (b - a).cross(d - a).Length / 2
    return area


class TestVDMeshCalculix(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.doc = FreeCAD.newDocument("VDMeshCalculix")
        cls.part = case.make_part(cls.doc)

    @classmethod
    def tearDownClass(cls):
        FreeCAD.closeDocument(cls.doc.Name)
        print_figures("TestVDMeshCalculix", "ccx")

    def test_pressure_on_the_hole_loads_its_area(self):
        # FreeCAD finds a constraint's element faces by their nodes lying on the CAD face within
        # its tolerance; vdmesh's random shift had left the hole's nodes up to 1e-6 off it, and a
        # pressure on the hole loaded 2.2 % of its area (a FreeCAD tester, 2026-11-30).
        import ObjectsFem
        from femtools import ccxtools
        shape = self.part.Shape
        hole = ["Face%d" % j for j, f in enumerate(shape.Faces, 1) if f.Surface.__class__.__name__ == "Cylinder"]
        self.assertEqual(len(hole), 1)
        analysis, solver = case.make_analysis(self.doc, self.part, "H")
        load = ObjectsFem.makeConstraintPressure(self.doc, "HolePressure")
        load.References = [(self.part, hole[0])]
        load.Pressure = 1.0
        analysis.addObject(load)
        for other in [o for o in analysis.Group if o.Name.startswith("PressureH")]:
            analysis.removeObject(other)
        obj = meshobject.create_mesh(self.part, engine.Parameters(size=1.0), analysis=analysis)[0]
        self.doc.recompute()
        fea = ccxtools.FemToolsCcx(analysis, solver)
        fea.update_objects()
        fea.setup_working_dir()
        fea.write_inp_file()
        cad = shape.getElement(hole[0]).Area
        area = loaded_area(fea.inp_file_name, obj.FemMesh)
        figure("pressure on the hole: loaded area %.4f of the CAD face's %.4f (%.2f %%)" % (area, cad, 100 * area / cad),
               "ccx")
        self.assertGreater(area / cad, 0.99)
        self.assertLess(area / cad, 1.0)

    def test_vdmesh_against_gmsh(self):
        part = self.part
        analysis, solver = case.make_analysis(self.doc, part, "V")
        obj, info, report, text = meshobject.create_mesh(part, engine.Parameters(size=VDMESH_SIZE, order=2),
                                                         analysis=analysis)
        self.assertIn(obj, analysis.Group)
        self.assertEqual(info["nodes_per_tetrahedron"], 10)
        vd = case.run_ccx(analysis, solver, obj)

        # one material per solid: the workbench added <Material>_Volumes groups, and FreeCAD's deck
        # gives each material exactly the tetrahedra of its solid
        groups = femmesh.group_ids(obj.FemMesh)
        for name, _, _ in case.MATERIALS:
            self.assertIn(name + "V_Volumes", groups)
        solid_of = {name: case.solid_name(part.Shape, pred) for (name, _, _), pred in
                    zip(case.MATERIALS, (lambda c: c.x < case.LENGTH / 2, lambda c: c.x > case.LENGTH / 2))}
        self.assertTrue(os.path.isfile(vd["inp_file"]), "no CalculiX deck %r" % vd["inp_file"])
        counts = material_element_counts(vd["inp_file"])
        for name, solid in solid_of.items():
            expected = len(obj.FemMesh.getGroupElements(groups[solid + "_Volumes"]))
            # the deck names a material after its object (name + the tag "V" of make_analysis)
            self.assertEqual(counts.get(name + "V"), expected, "%s elements of %s" % (name, solid))

        g_analysis, g_solver = case.make_analysis(self.doc, part, "G")
        gmsh = case.gmsh_mesh(self.doc, part, GMSH_SIZE, 2, "")
        gm = case.run_ccx(g_analysis, g_solver, gmsh)
        self.assertEqual(gm["nodes_per_tetrahedron"], 10)

        for key in ("max_displacement",):
            rel = abs(vd[key] - gm[key]) / abs(gm[key])
            figure("%s: vdmesh (size %g, %d nodes, %d tets) %.6g, Gmsh (size %g, %d nodes, %d tets) %.6g: %.2f %%"
                   % (key, VDMESH_SIZE, vd["nodes"], vd["tetrahedra"], vd[key], GMSH_SIZE, gm["nodes"],
                      gm["tetrahedra"], gm[key], 100 * rel), "ccx")
            self.assertLess(rel, AGREEMENT, key)
        for key in ("P_alu", "P_steel_over_hole"):
            figure("von Mises at %s: vdmesh %.5g, Gmsh %.5g (not asserted: not converged, see above)"
                   % (key, vd[key], gm[key]), "ccx")
        figure("CalculiX through FemToolsCcx: vdmesh %.0f s, Gmsh %.0f s; materials per solid: %s"
               % (vd["ccx_seconds"], gm["ccx_seconds"], counts), "ccx")
