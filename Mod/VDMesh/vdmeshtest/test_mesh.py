"""Headless tests of the workbench's Mesh code path (vdmeshwb.meshobject.create_mesh, as the Mesh
command runs it). Part of TestVDMeshApp: `freecadcmd -t TestVDMeshApp.TestVDMeshWorkbench -M Mod/VDMesh`.

Meshes (1) a box 10x10x4 with a hole of diameter 4 (Part::Cut of Part::Box and Part::Cylinder) and
(2) a BooleanFragments of two touching boxes of different sizes (two solids, one interface face);
checks the FemMesh: tetrahedra with FemMesh's orientation, Solid<i>_Volumes/_Nodes per solid and
Face<j>_Faces/_Nodes per face, volume per solid within 1 % of FreeCAD's, the face numbering against
FreeCAD's Face<j> (vdmesh's per-face CAD areas, and the nodes of each face group lying on that face);
the analysis; recompute with another size; export through `vdmesh convert`; bad geometry (an open
shell made a solid: vdmesh exit 3) gives a VDMeshError and leaves the document unchanged; the
materials' groups (References, none); undo and redo of a Size change; save, reopen and recompute;
(3) a plain Part.makeCompound of a 20x20x10 box and a 10x10x5 block on its top overhanging by half
(vdmesh fuses them): all 12 Face<j>_Faces groups have FreeCAD's Face<j>.Area (1e-9 relative), so the
contact patch is in both the box's top and the block's bottom, and all Face<j>_Nodes lie on Face<j>
(within 1e-9).
Export without the kept deck (its folder removed, the document reopened) writes the same *SURFACE,
*NSET and *ELSET sets as the kept deck, and vdmesh reads them back as Gmsh physical groups; the
vdmesh-keep-* folders do not pile up (undo, redo, remesh, delete, close), nor do failed runs' folders.
Tests 10-16: a part changed while meshing leaves the mesh to recompute; a mesh joining an analysis
gets its materials' groups; a part deleted (or its document closed) while meshing stops the run;
remesh is one undo step; a failed create_mesh without undo removes its object; export to an
unwritable path and bad geometry give errors that name the path and the part.
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


def boolean_fragments(doc, name, *boxes):
    """A BooleanFragments (Standard) of cubes given as (name, edge, corner): touching solids."""
    import BOPTools.SplitFeatures
    parts = []
    for label, edge, corner in boxes:
        box = doc.addObject("Part::Box", label)
        box.Length = box.Width = box.Height = edge
        box.Placement.Base = corner
        parts.append(box)
    doc.recompute()
    FreeCAD.setActiveDocument(doc.Name)  # makeBooleanFragments adds to the active document
    bf = BOPTools.SplitFeatures.makeBooleanFragments(name=name)
    bf.Objects = parts
    bf.Mode = "Standard"
    doc.recompute()
    return bf



def meshed_box_with_undo(test, doc_name):
    """A document recording undo with a 20 x 10 x 10 box meshed at size 3: (doc, box, mesh object)."""
    doc = FreeCAD.newDocument(doc_name)
    test.addCleanup(close_if_open, doc.Name)
    doc.UndoMode = 1
    box = doc.addObject("Part::Box", "Box")
    box.Length, box.Width, box.Height = 20, 10, 10
    doc.recompute()
    return doc, box, meshobject.create_mesh(box, engine.Parameters(size=3.0))[0]

class MeshChecks:
    def check_mesh(self, name, obj, part_shape, info, report):
        fm = obj.FemMesh
        self.assertGreater(fm.VolumeCount, 0)
        self.assertEqual(fm.VolumeCount, info["tetrahedra"])
        groups = femmesh.group_ids(fm)
        solids, faces = part_shape.Solids, part_shape.Faces
        for i in range(1, len(solids) + 1):
            self.assertIn("Solid%d_Volumes" % i, groups)
            self.assertIn("Solid%d_Nodes" % i, groups)
            self.assertEqual(fm.getGroupElementType(groups["Solid%d_Volumes" % i]), "Volume")
        for j in range(1, len(faces) + 1):
            self.assertIn("Face%d_Faces" % j, groups)
            self.assertIn("Face%d_Nodes" % j, groups)
            self.assertEqual(fm.getGroupElementType(groups["Face%d_Faces" % j]), "Face")
        self.assertNotIn("Solid%d_Volumes" % (len(solids) + 1), groups)
        self.assertNotIn("Face%d_Faces" % (len(faces) + 1), groups)
        # every tetrahedron in exactly one solid group
        in_groups = sum(len(fm.getGroupElements(groups["Solid%d_Volumes" % i])) for i in range(1, len(solids) + 1))
        self.assertEqual(in_groups, fm.VolumeCount)

        # volumes: whole mesh and per solid against FreeCAD's (orientation: FemMesh keeps them negative)
        total, negative, count = femmesh.tet_volumes(fm)
        self.assertEqual(negative, count, "tetrahedra must have FemMesh's (negative) orientation")
        err = abs(total - part_shape.Volume) / part_shape.Volume
        self.assertLess(err, 0.01)
        figure("%s: %d nodes, %d tetrahedra, %d solid groups, %d face groups; volume FreeCAD %.6g, mesh %.6g (%.4f %%)"
               % (name, fm.NodeCount, fm.VolumeCount, len(solids), len(faces), part_shape.Volume, total, 100 * err))
        for i, s in enumerate(solids, 1):
            v, _, _ = femmesh.tet_volumes(fm, fm.getGroupElements(groups["Solid%d_Volumes" % i]))
            e = abs(v - s.Volume) / s.Volume
            figure("  Solid%d: FreeCAD %.6g, mesh %.6g (%.4f %%)" % (i, s.Volume, v, 100 * e))
            self.assertLess(e, 0.01, "Solid%d" % i)

        # face numbering: vdmesh's CAD area of Face<j> is FreeCAD's Face<j>.Area ...
        areas = {a["name"]: a["cad"] for a in report["cad"]["areas"]}
        self.assertEqual(len(areas), len(faces))
        for j, f in enumerate(faces, 1):
            self.assertAlmostEqual(areas["Face%d" % j] / f.Area, 1.0, places=4, msg="Face%d area" % j)
        # ... and the nodes of group Face<j> lie on FreeCAD's Face<j> (and not all on another face)
        nodes = fm.Nodes
        tol = 1e-3 * part_shape.BoundBox.DiagonalLength
        for j, f in enumerate(faces, 1):
            ids = fm.getGroupElements(groups["Face%d_Nodes" % j])
            self.assertGreaterEqual(len(ids), 3)
            sample = ids[:: max(1, len(ids) // 40)]
            worst = max(f.distToShape(Part.Vertex(nodes[n]))[0] for n in sample)
            self.assertLess(worst, tol, "Face%d nodes off FreeCAD's Face%d by %g" % (j, j, worst))
        # the face triangles of Face<j> sum to its area
        for j, f in enumerate(faces, 1):
            a = 0.0
            for e in fm.getGroupElements(groups["Face%d_Faces" % j]):
                p = [nodes[n] for n in fm.getElementNodes(e)]
                a += (p[1] - p[0]).cross(p[2] - p[0]).Length / 2
            self.assertLess(abs(a - f.Area) / f.Area, 0.01, "Face%d triangles area" % j)
        figure("  face numbering: %d faces, areas and node positions match FreeCAD's Face<j>" % len(faces))


class TestVDMeshWorkbench(unittest.TestCase, MeshChecks):
    @classmethod
    def setUpClass(cls):
        cls.doc = FreeCAD.newDocument("VDMeshTest")
        figure("vdmesh engine: %s" % engine.engine_name())

    @classmethod
    def tearDownClass(cls):
        FreeCAD.closeDocument(cls.doc.Name)
        print_figures("TestVDMeshWorkbench")

    def test_1_box_with_hole(self):
        import ObjectsFem
        cut = add_box_with_hole(self.doc)
        self.assertEqual(len(cut.Shape.Solids), 1)
        self.assertEqual(len(cut.Shape.Faces), 7)
        analysis = ObjectsFem.makeAnalysis(self.doc, "Analysis")
        t = time.time()
        obj, info, report, text = meshobject.create_mesh(cut, engine.Parameters(size=1.0), analysis=analysis)
        figure("box with hole, size 1: create_mesh %.2f s" % (time.time() - t))
        self.assertEqual(obj.TypeId, "Fem::FemMeshObjectPython")
        self.assertIs(obj.Part, cut)
        self.assertIn(obj, analysis.Group)
        self.assertAlmostEqual(obj.Size.Value, 1.0)
        self.assertTrue(os.path.isfile(obj.OutputFile))
        self.check_mesh("box with hole", obj, cut.Shape, info, report)
        self.assertIn("tetrahedra", meshobject.mesh_summary(info, report))

        # recompute with other parameters re-runs vdmesh
        before = obj.FemMesh.VolumeCount
        obj.Size = 2.0
        obj.Interior = False
        self.doc.recompute()
        self.assertNotIn("Invalid", obj.State)
        after = obj.FemMesh.VolumeCount
        self.assertGreater(after, 0)
        self.assertLess(after, before)
        total, _, _ = femmesh.tet_volumes(obj.FemMesh)
        self.assertLess(abs(total - cut.Shape.Volume) / cut.Shape.Volume, 0.01)
        figure("  recompute at size 2 without interior vertices: %d -> %d tetrahedra" % (before, after))

        # export through vdmesh convert, from the kept deck and from the FemMesh alone
        out = tempfile.mkdtemp(prefix="vdmesh-fc-export-")
        self.addCleanup(shutil.rmtree, out, True)
        for ext in (".vtu", ".msh", ".inp"):
            path = meshobject.export_mesh(obj, os.path.join(out, "m" + ext))
            self.assertGreater(os.path.getsize(path), 1000)
        kept = obj.OutputFile
        obj.OutputFile = ""
        path = meshobject.export_mesh(obj, os.path.join(out, "fromfemmesh.vtu"))
        self.assertGreater(os.path.getsize(path), 1000)
        obj.OutputFile = kept
        proc = engine._run([engine.find_binary(), "info", os.path.join(out, "m.msh")])
        self.assertEqual(proc.returncode, 0, proc.stderr)
        figure("  export: .vtu .msh .inp through vdmesh convert, and .vtu from the FemMesh alone")
        # The deck changed since the run (every document named alike shared
        # one folder, and Export wrote another document's mesh): Export goes
        # by the FemMesh, and each run keeps its deck in a folder of its own.
        with open(obj.OutputFile, "w") as f:
            f.write("*NODE\n1, 0, 0, 0\n2, 1, 0, 0\n3, 0, 1, 0\n4, 0, 0, 1\n"
                    "*ELEMENT, TYPE=C3D4, ELSET=Other\n1, 1, 2, 3, 4\n")
        path = meshobject.export_mesh(obj, os.path.join(out, "changed.inp"))
        proc = engine._run([engine.find_binary(), "info", path])
        self.assertEqual(proc.returncode, 0, proc.stderr)
        self.assertIn("tetrahedra %d" % obj.FemMesh.VolumeCount, proc.stdout)
        first = os.path.dirname(obj.OutputFile)
        obj.Seed = obj.Seed + 1
        self.doc.recompute()
        self.assertNotEqual(os.path.dirname(obj.OutputFile), first)
        self.assertFalse(os.path.exists(first))

    def test_2_boolean_fragments(self):
        bf = boolean_fragments(self.doc, "Fragments", ("BigBox", 10, Vector(0, 0, 0)), ("SmallBox", 5, Vector(10, 2, 3)))
        shape = bf.Shape
        self.assertEqual(len(shape.Solids), 2)
        t = time.time()
        obj, info, report, text = meshobject.create_mesh(bf, engine.Parameters(size=1.5))
        figure("BooleanFragments of two touching boxes (%d faces), size 1.5: create_mesh %.2f s"
               % (len(shape.Faces), time.time() - t))
        self.assertEqual(report["cad"]["solids"], 2)
        self.assertEqual(report["cad"]["interface_faces"], 1)
        self.check_mesh("fragments", obj, shape, info, report)
        # the interface face has nodes of both solids
        groups = femmesh.group_ids(obj.FemMesh)
        shared = [j for j, f in enumerate(shape.Faces, 1)
                  if sum(any(f.isSame(g) for g in s.Faces) for s in shape.Solids) == 2]
        self.assertEqual(len(shared), 1)
        fn = set(obj.FemMesh.getGroupElements(groups["Face%d_Nodes" % shared[0]]))
        for i in (1, 2):
            self.assertTrue(fn <= set(obj.FemMesh.getGroupElements(groups["Solid%d_Nodes" % i])))
        figure("  interface Face%d: %d nodes, in both Solid1_Nodes and Solid2_Nodes" % (shared[0], len(fn)))

    def test_2b_solid_inside_another_is_said(self):
        # A compound of a box and a box inside it: the overlap goes to Solid1, so Solid2 is not
        # in the mesh, and the workbench said nothing of it.
        doc = self.doc
        part = doc.addObject("Part::Feature", "Inclusion")
        inner = Part.makeBox(2, 2, 2, Vector(4, 4, 4))
        part.Shape = Part.makeCompound([Part.makeBox(10, 10, 10), inner])
        doc.recompute()
        obj, info, report, text = meshobject.create_mesh(part, engine.Parameters(size=2.0))
        summary = meshobject.mesh_summary(info, report)
        self.assertIn("warning: overlapping solids: Solid1 and Solid2 share a volume of 8", summary)
        self.assertIn("Solid2 is not in the mesh", summary)
        figure("  a box inside a box: %s" % summary.splitlines()[0])

    def test_2c_material_groups_follow_their_references(self):
        # A material's References changed after meshing: recompute renews <Material>_Volumes
        # without meshing again (they kept the solids named before, and CalculiX would have
        # given each solid the other's material).
        import ObjectsFem
        doc = self.doc
        bf = boolean_fragments(doc, "TwoMaterials", ("LeftBox", 10, Vector(0, 0, 0)), ("RightBox", 10, Vector(10, 0, 0)))
        analysis = ObjectsFem.makeAnalysis(doc, "MaterialAnalysis")
        steel, alu = (ObjectsFem.makeMaterialSolid(doc, n) for n in ("Steel", "Alu"))
        steel.References = [(bf, "Solid1")]
        alu.References = [(bf, "Solid2")]
        analysis.addObject(steel)
        analysis.addObject(alu)
        obj, info, report, text = meshobject.create_mesh(bf, engine.Parameters(size=3.0), analysis=analysis)

        def volumes(group):
            return set(obj.FemMesh.getGroupElements(femmesh.group_ids(obj.FemMesh)[group]))

        solid1, solid2 = volumes("Solid1_Volumes"), volumes("Solid2_Volumes")
        self.assertEqual(volumes(steel.Name + "_Volumes"), solid1)
        self.assertEqual(volumes(alu.Name + "_Volumes"), solid2)
        deck = obj.OutputFile
        steel.References = [(bf, "Solid2")]
        alu.References = [(bf, "Solid1")]
        doc.recompute()
        self.assertEqual(volumes(steel.Name + "_Volumes"), solid2)
        self.assertEqual(volumes(alu.Name + "_Volumes"), solid1)
        self.assertEqual(obj.OutputFile, deck)  # not meshed again
        figure("  materials swapped: groups renewed on recompute, mesh kept (%d tetrahedra)" % obj.FemMesh.VolumeCount)

    def test_2d_material_without_references_takes_the_rest(self):
        # FreeCAD reads a solid material without References beside others as "the rest": it gave
        # Steel every tetrahedron, Alu's too, and the CalculiX writer's count check failed.
        import ObjectsFem
        doc = self.doc
        bf = boolean_fragments(doc, "SteelAndAlu", ("SteelBox", 10, Vector(0, 30, 0)), ("AluBox", 10, Vector(10, 30, 0)))
        analysis = ObjectsFem.makeAnalysis(doc, "RestAnalysis")
        steel = ObjectsFem.makeMaterialSolid(doc, "RestSteel")
        analysis.addObject(steel)
        obj, info, report, text = meshobject.create_mesh(bf, engine.Parameters(size=3.0), analysis=analysis)

        def volumes(group):
            return set(obj.FemMesh.getGroupElements(femmesh.group_ids(obj.FemMesh)[group]))

        self.assertEqual(volumes(steel.Name + "_Volumes"), set(obj.FemMesh.Volumes))  # the only material
        alu = ObjectsFem.makeMaterialSolid(doc, "RestAlu")
        alu.References = [(bf, "Solid2")]
        analysis.addObject(alu)
        obj.touch()
        doc.recompute()
        steel_set, alu_set = volumes(steel.Name + "_Volumes"), volumes(alu.Name + "_Volumes")
        self.assertEqual(alu_set, volumes("Solid2_Volumes"))
        self.assertEqual(steel_set, volumes("Solid1_Volumes"))
        self.assertFalse(steel_set & alu_set)
        figure("  a material without References beside one on Solid2: %d + %d of %d tetrahedra"
               % (len(steel_set), len(alu_set), obj.FemMesh.VolumeCount))

    def test_2e_plain_compound_contact_in_both_faces_groups(self):
        # Touching solids as a plain compound: vdmesh fuses them, and the contact patch (half the
        # block's bottom, 10 x 5 on the big box's top) lies on two FreeCAD faces. Its facets went to
        # the lower face number alone (the big box's top, Face6): Face11_Faces, the block's bottom,
        # had 50 of its 100 mm2. Now the patch is in both faces' groups.
        doc = self.doc
        part = doc.addObject("Part::Feature", "Overhang")
        part.Shape = Part.makeCompound([Part.makeBox(20, 20, 10), Part.makeBox(10, 10, 5, Vector(15, 5, 10))])
        doc.recompute()
        shape = part.Shape
        self.assertEqual((len(shape.Solids), len(shape.Faces)), (2, 12))
        t = time.time()
        obj, info, report, text = meshobject.create_mesh(part, engine.Parameters(size=2.0))
        seconds = time.time() - t
        fm = obj.FemMesh
        groups = femmesh.group_ids(fm)
        nodes = fm.Nodes
        self.assertNotIn("Face13_Faces", groups)
        worst_area = worst_node = 0.0
        for j, f in enumerate(shape.Faces, 1):
            self.assertIn("Face%d_Faces" % j, groups)
            a = 0.0
            for e in fm.getGroupElements(groups["Face%d_Faces" % j]):
                p = [nodes[n] for n in fm.getElementNodes(e)[:3]]
                a += (p[1] - p[0]).cross(p[2] - p[0]).Length / 2
            rel = abs(a - f.Area) / f.Area
            worst_area = max(worst_area, rel)
            self.assertLess(rel, 1e-9, "Face%d_Faces: %.9g mm2, FreeCAD's Face%d %.9g" % (j, a, j, f.Area))
            ids = fm.getGroupElements(groups["Face%d_Nodes" % j])
            self.assertGreaterEqual(len(ids), 3)
            d = max(f.distToShape(Part.Vertex(nodes[n]))[0] for n in ids)
            worst_node = max(worst_node, d)
            self.assertLess(d, 1e-9, "Face%d_Nodes off FreeCAD's Face%d by %g" % (j, j, d))
        # the contact patch: nodes in both the big box's top and the block's bottom
        top, bottom = (set(fm.getGroupElements(groups["Face%d_Nodes" % j])) for j in (6, 11))
        both = [nodes[n] for n in top & bottom]
        self.assertTrue(both and all(15 - 1e-9 <= p.x <= 20 + 1e-9 and 5 - 1e-9 <= p.y <= 15 + 1e-9 for p in both))
        self.assertAlmostEqual(min(p.x for p in both), 15, places=9)  # the whole patch, not only x = 20
        figure("plain compound, block overhanging by half (size 2, %.2f s): %d tetrahedra; 12 face groups, "
               "areas within %.2g of FreeCAD's, nodes within %.2g; contact patch: %d nodes in Face6 and Face11"
               % (seconds, fm.VolumeCount, worst_area, worst_node, len(both)))

    def test_4_module_and_program_give_the_same_mesh(self):
        # ctest says which engine this build must use: the module (Release) or the program.
        core = engine.core_module()
        expected = os.environ.get("VDMESH_EXPECT_ENGINE", "")
        if expected:
            self.assertEqual("module" if core else "program", expected, engine.engine_name())
        if core is None:
            self.skipTest("the vdmesh module is not importable here: only the program was used")
        shape = Part.makeCylinder(2, 5)
        params = engine.Parameters(size=1.0, seed=7)
        inp_module, report_module, _ = engine.mesh_shape(shape, params)
        self.addCleanup(shutil.rmtree, os.path.dirname(inp_module), True)
        os.environ["VDMESH_ENGINE"] = "program"
        try:
            self.assertIsNone(engine.core_module())
            inp_program, report_program, _ = engine.mesh_shape(shape, params)
            self.addCleanup(shutil.rmtree, os.path.dirname(inp_program), True)
        finally:
            del os.environ["VDMESH_ENGINE"]
        a, b = inpreader.read_inp(inp_module), inpreader.read_inp(inp_program)
        self.assertGreater(len(a.elements), 100)
        self.assertEqual(a.elements, b.elements)
        self.assertEqual(a.nodes, b.nodes)
        self.assertEqual(a.surfaces, b.surfaces)
        self.assertEqual(report_module["quality"]["min_dihedral_deg"], report_program["quality"]["min_dihedral_deg"])
        figure("module and program, same cylinder and seed: the same %d nodes and %d tetrahedra"
               % (len(a.nodes), len(a.elements)))

    def test_5_stop_while_meshing(self):
        # The task panel's Stop: meshing runs on a worker thread while this one runs `idle` (the
        # panel's event loop); a set CancelRequest stops the module (its CancelToken) or kills the
        # program, and the document is left as it was. Size 0.15 would take 8 s (2.1M tetrahedra);
        # size 0.25 now ends in 1.2 s, about when the request comes.
        cut = self.doc.getObject("BoxWithHole") or add_box_with_hole(self.doc)
        engines = ["program"] + (["module"] if engine.core_module() is not None else [])
        for name in engines:
            if name == "program":
                os.environ["VDMESH_ENGINE"] = "program"
            try:
                names = sorted(o.Name for o in self.doc.Objects)
                cancel, calls, sent = engine.CancelRequest(), [], []
                t0 = time.monotonic()

                def idle():
                    calls.append(1)
                    if not sent and time.monotonic() - t0 > 1.0:
                        sent.append(time.monotonic())
                        cancel.set()

                with self.assertRaises(engine.VDMeshCancelled):
                    meshobject.create_mesh(cut, engine.Parameters(size=0.15), cancel=cancel, idle=idle)
                stopped = time.monotonic() - sent[0]
                self.assertLess(stopped, 5.0)
                self.assertGreater(len(calls), 20, "the calling thread kept running")
                self.assertEqual(sorted(o.Name for o in self.doc.Objects), names)
                figure("Stop (%s): stopped %.2f s after the request, idle ran %d times, document unchanged"
                       % (name, stopped, len(calls)))
            finally:
                os.environ.pop("VDMESH_ENGINE", None)

    def test_3_bad_geometry_leaves_document_unchanged(self):
        doc = self.doc
        faces = Part.makeBox(1, 1, 1).Faces[:5]        # no lid
        bad = doc.addObject("Part::Feature", "OpenSolid")
        bad.Shape = Part.Solid(Part.Shell(faces))
        doc.recompute()
        names = sorted(o.Name for o in doc.Objects)
        with self.assertRaises(engine.VDMeshError) as ctx:
            meshobject.create_mesh(bad)
        self.assertEqual(ctx.exception.code, 3)
        self.assertEqual(sorted(o.Name for o in doc.Objects), names)
        figure("open solid: VDMeshError exit %s, document unchanged: %s"
               % (ctx.exception.code, ctx.exception.message.splitlines()[0]))
        # a shape without solids is refused before vdmesh runs
        sheet = doc.addObject("Part::Feature", "Sheet")
        sheet.Shape = Part.makePlane(1, 1)
        doc.recompute()
        names = sorted(o.Name for o in doc.Objects)
        with self.assertRaises(engine.VDMeshError):
            meshobject.create_mesh(sheet)
        self.assertEqual(sorted(o.Name for o in doc.Objects), names)

    def test_6_undo_gives_back_the_mesh_of_the_properties(self):
        # Undo restores Size and MeshInputs but not the FemMesh: the undone mesh stayed through
        # recompute, touch and save; redo brings back a deck that is not the FemMesh's.
        doc = FreeCAD.newDocument("VDMeshUndo")
        self.addCleanup(FreeCAD.closeDocument, doc.Name)
        doc.UndoMode = 1
        box = doc.addObject("Part::Box", "Box")
        box.Length, box.Width, box.Height = 20, 10, 10
        doc.recompute()
        obj, info, report, text = meshobject.create_mesh(box, engine.Parameters(size=3.0))
        at3 = obj.FemMesh.VolumeCount
        doc.openTransaction("Size 5")
        obj.Size = 5.0
        doc.recompute()
        doc.commitTransaction()
        at5 = obj.FemMesh.VolumeCount
        self.assertLess(at5, at3)
        doc.undo()
        self.assertAlmostEqual(obj.Size.Value, 3.0)
        self.assertIsNone(meshobject.kept_deck(obj))  # its folder is gone: Export writes the FemMesh
        doc.recompute()
        self.assertEqual(obj.FemMesh.VolumeCount, at3)
        self.assertIsNotNone(meshobject.kept_deck(obj))
        doc.redo()
        self.assertAlmostEqual(obj.Size.Value, 5.0)
        self.assertEqual(obj.FemMesh.VolumeCount, at3)
        self.assertIsNone(meshobject.kept_deck(obj))  # the size-5 deck is there, but not the FemMesh's
        doc.recompute()
        self.assertEqual(obj.FemMesh.VolumeCount, at5)
        figure("undo of Size 3 -> 5: %d -> %d tetrahedra, undo + recompute %d, redo + recompute %d"
               % (at3, at5, at3, at5))

    def test_7_reopened_document_keeps_its_mesh(self):
        # The part's BREP text changes on save and reload (-7.3478807948841188e-16 comes back as
        # -7.3000000000000003e-16): every recompute of a reopened document meshed again.
        doc = FreeCAD.newDocument("VDMeshReopen")
        cut = add_box_with_hole(doc)
        obj, info, report, text = meshobject.create_mesh(cut, engine.Parameters(size=2.0))
        name, deck, count = obj.Name, obj.OutputFile, obj.FemMesh.VolumeCount
        folder = tempfile.mkdtemp(prefix="vdmesh-fc-reopen-")
        self.addCleanup(shutil.rmtree, folder, True)
        doc.saveAs(os.path.join(folder, "reopen.FCStd"))
        FreeCAD.closeDocument(doc.Name)
        doc = FreeCAD.openDocument(os.path.join(folder, "reopen.FCStd"))
        self.addCleanup(FreeCAD.closeDocument, doc.Name)
        obj, cut = doc.getObject(name), doc.getObject("BoxWithHole")
        doc.recompute()
        self.assertEqual(obj.OutputFile, deck)  # not meshed again
        cut.touch()  # the part's shape made again, not the one read back
        doc.recompute()
        self.assertEqual(obj.OutputFile, deck)
        self.assertEqual(obj.FemMesh.VolumeCount, count)
        doc.getObject("Box").Length = 12  # a real change of the part meshes again
        doc.recompute()
        self.assertNotEqual(obj.OutputFile, deck)
        self.assertNotEqual(obj.FemMesh.VolumeCount, count)
        figure("saved, reopened, recomputed (part too): mesh kept (%d tetrahedra); box 12 long: %d"
               % (count, obj.FemMesh.VolumeCount))

    def test_8_export_without_the_kept_deck_keeps_the_face_sets(self):
        # Without the kept deck (undo or redo, its temporary folder removed, the document reopened)
        # Export writes the FemMesh, and wrote its regions only: no *SURFACE or face node set was
        # left for a *DSLOAD or *BOUNDARY to name. The part of test_2e (a contact patch in two
        # faces' groups, listed through one solid's elements) in an analysis with a material on
        # Solid2 and one without References (their <Material>_Volumes groups beside the regions').
        import ObjectsFem
        doc = FreeCAD.newDocument("VDMeshExport")
        self.addCleanup(close_if_open, doc.Name)
        part = doc.addObject("Part::Feature", "Overhang")
        part.Shape = Part.makeCompound([Part.makeBox(20, 20, 10), Part.makeBox(10, 10, 5, Vector(15, 5, 10))])
        analysis = ObjectsFem.makeAnalysis(doc, "Analysis")
        steel, alu = (ObjectsFem.makeMaterialSolid(doc, n) for n in ("Steel", "Alu"))
        alu.References = [(part, "Solid2")]
        analysis.addObject(steel)
        analysis.addObject(alu)
        doc.recompute()
        obj, info, report, text = meshobject.create_mesh(part, engine.Parameters(size=2.0), analysis=analysis)
        out = tempfile.mkdtemp(prefix="vdmesh-fc-export-")
        self.addCleanup(shutil.rmtree, out, True)
        self.assertIsNotNone(meshobject.kept_deck(obj))
        kept_path = meshobject.export_mesh(obj, os.path.join(out, "kept.inp"))
        kept = inpreader.read_inp(kept_path)
        self.assertEqual(len(kept.surfaces), 12)

        shutil.rmtree(os.path.dirname(obj.OutputFile))  # the temporary folder was cleaned
        self.assertIsNone(meshobject.kept_deck(obj))
        removed_path = meshobject.export_mesh(obj, os.path.join(out, "removed.inp"))
        self.check_same_deck(kept, inpreader.read_inp(removed_path), "kept deck removed")

        # reopened: the FemMesh read back from the UNV the document keeps it in
        name = obj.Name
        doc.saveAs(os.path.join(out, "export.FCStd"))
        FreeCAD.closeDocument(doc.Name)
        doc = FreeCAD.openDocument(os.path.join(out, "export.FCStd"))
        self.addCleanup(close_if_open, doc.Name)
        obj = doc.getObject(name)
        self.assertIsNone(meshobject.kept_deck(obj))
        reopened_path = meshobject.export_mesh(obj, os.path.join(out, "reopened.inp"))
        self.check_same_deck(kept, inpreader.read_inp(reopened_path), "reopened document")

        # vdmesh reads the surfaces back: the Gmsh file has the same physical names from either deck
        names = {}
        for label, path in (("kept", kept_path), ("removed", removed_path)):
            msh = os.path.join(out, label + ".msh")
            proc = engine._run([engine.find_binary(), "convert", path, msh])
            self.assertEqual(proc.returncode, 0, proc.stderr)
            names[label] = physical_names(msh)
        self.assertEqual(names["removed"], names["kept"])
        faces = sorted((n for d, n in names["removed"] if d == 2), key=femmesh._natural)
        self.assertEqual(faces, ["Face%d" % j for j in range(1, 13)])
        self.assertEqual(sorted(n for d, n in names["removed"] if d == 3), ["Solid1", "Solid2"])
        figure("export without the kept deck (removed, and the document reopened): the same %d *SURFACEs "
               "(%d element sides, Face6 %d and Face11 %d of them) and %d node sets as the kept deck; "
               "vdmesh convert to .msh: %d physical surfaces, %d volumes"
               % (len(kept.surfaces), sum(len(s) for s in kept.surfaces.values()), len(kept.surfaces["Face6"]),
                  len(kept.surfaces["Face11"]), len(kept.nsets), len(faces), len(names["removed"]) - len(faces)))

    def check_same_deck(self, kept, other, what):
        """other (Export from the FemMesh) has the kept deck's surfaces, each side of a tetrahedron
        the same, node sets, element sets, nodes and elements."""
        self.assertEqual(sorted(other.surfaces, key=femmesh._natural), sorted(kept.surfaces, key=femmesh._natural),
                         what)
        for name, sides in kept.surfaces.items():
            self.assertEqual(len(other.surfaces[name]), len(sides), "%s: %s" % (what, name))
            self.assertEqual(sorted(other.surfaces[name]), sorted(sides), "%s: %s" % (what, name))
        self.assertEqual({k: sorted(v) for k, v in other.nsets.items()},
                         {k: sorted(v) for k, v in kept.nsets.items()}, what)
        self.assertEqual({k: sorted(v) for k, v in other.elsets.items()},
                         {k: sorted(v) for k, v in kept.elsets.items()}, what)
        self.assertEqual(sorted(other.nodes), sorted(kept.nodes), what)
        worst = max(max(abs(a - b) for a, b in zip(kept.nodes[n], other.nodes[n])) for n in kept.nodes)
        self.assertLess(worst, 1e-9, what)
        self.assertEqual(other.elements, kept.elements, what)

    def test_9_keep_folders_do_not_pile_up(self):
        # Each run keeps its deck in a vdmesh-keep-* folder. Only the previous run's was removed:
        # after undo or redo (OutputFile an older run's) the newer one stayed, and a deleted
        # object's and a closed document's stayed too (a session of tests left over 200 in /tmp).
        # A temporary folder of this test's own, so that nobody else's runs count.
        tmp = tempfile.mkdtemp(prefix="vdmesh-fc-tmpdir-")
        self.addCleanup(shutil.rmtree, tmp, True)
        self.addCleanup(setattr, tempfile, "tempdir", tempfile.tempdir)
        tempfile.tempdir = tmp

        def keep_folders():
            return len([n for n in os.listdir(tmp) if n.startswith("vdmesh-keep-")])

        counts = []
        doc, box, obj = meshed_box_with_undo(self, "VDMeshKeep")
        at3 = obj.FemMesh.VolumeCount
        counts.append(("mesh", keep_folders()))
        doc.openTransaction("Size 5")
        obj.Size = 5.0
        doc.recompute()
        doc.commitTransaction()
        at5 = obj.FemMesh.VolumeCount
        counts.append(("Size 5", keep_folders()))
        doc.undo()
        counts.append(("undo", keep_folders()))
        doc.recompute()
        self.assertEqual(obj.FemMesh.VolumeCount, at3)  # undo works as before
        self.assertIsNotNone(meshobject.kept_deck(obj))
        counts.append(("recompute", keep_folders()))
        doc.redo()
        counts.append(("redo", keep_folders()))
        self.assertIsNone(meshobject.kept_deck(obj))  # the FemMesh is not the size-5 run's: Export writes it
        doc.recompute()
        self.assertEqual(obj.FemMesh.VolumeCount, at5)
        self.assertIsNotNone(meshobject.kept_deck(obj))
        counts.append(("recompute", keep_folders()))
        # As after reopening a document: the proxy lists no folder, OutputFile names one.
        obj.Proxy.keep_folders = []
        obj.Seed = 2
        doc.recompute()
        counts.append(("reopened and remeshed", keep_folders()))
        doc.removeObject(obj.Name)
        counts.append(("deleted", keep_folders()))
        # closing a document removes its objects' folders (FreeCAD closes them all on exit)
        meshobject.create_mesh(box, engine.Parameters(size=4.0))
        meshobject.create_mesh(box, engine.Parameters(size=5.0))
        counts.append(("two more objects", keep_folders()))
        FreeCAD.closeDocument(doc.Name)
        counts.append(("document closed", keep_folders()))

        # a refused part and a stopped run leave no folder either
        doc = FreeCAD.newDocument("VDMeshKeepFailures")
        self.addCleanup(close_if_open, doc.Name)
        bad = doc.addObject("Part::Feature", "OpenSolid")
        bad.Shape = Part.Solid(Part.Shell(Part.makeBox(1, 1, 1).Faces[:5]))
        doc.recompute()
        with self.assertRaises(engine.VDMeshError):
            meshobject.create_mesh(bad)
        cancel = engine.CancelRequest()
        cancel.set()
        with self.assertRaises(engine.VDMeshCancelled):
            meshobject.create_mesh(box_shape_object(doc), engine.Parameters(size=0.5), cancel=cancel)
        left = sorted(os.listdir(tmp))
        figure("vdmesh-keep-* folders after each step: %s; then a refused part and a stopped run: %d entries "
               "left in the temporary folder" % (", ".join("%s %d" % c for c in counts), len(left)))
        expected = {"deleted": 0, "document closed": 0, "two more objects": 2}  # else the current run's 1
        self.assertEqual(counts, [(step, expected.get(step, 1)) for step, _ in counts])
        self.assertEqual(left, [])


    def private_tmpdir(self):
        """A temporary folder of this test's own (tempfile.tempdir), so that nobody else's runs count."""
        tmp = tempfile.mkdtemp(prefix="vdmesh-fc-tmpdir-")
        self.addCleanup(shutil.rmtree, tmp, True)
        self.addCleanup(setattr, tempfile, "tempdir", tempfile.tempdir)
        tempfile.tempdir = tmp
        return tmp

    def test_10_part_changed_while_meshing_is_meshed_again(self):
        # The task panel's event loop runs while meshing, and a user may edit the part meanwhile.
        # The fingerprint was taken after meshing, from the changed part: the old mesh stayed
        # "Up-to-date" through every recompute.
        doc = FreeCAD.newDocument("VDMeshStale")
        self.addCleanup(close_if_open, doc.Name)
        box = doc.addObject("Part::Box", "Box")
        box.Length, box.Width, box.Height = 20, 10, 10
        doc.recompute()
        edited = []

        def idle():  # the property editor, through the panel's event loop
            if not edited:
                edited.append(1)
                box.Length = 40
                doc.recompute()

        obj, info, report, text = meshobject.create_mesh(box, engine.Parameters(size=2.0), idle=idle)
        self.assertAlmostEqual(obj.FemMesh.BoundBox.XLength, 20.0, places=6)  # the part as it was meshed
        self.assertIn("Touched", obj.State)
        self.assertTrue(info["stale"])
        doc.recompute()
        self.assertAlmostEqual(obj.FemMesh.BoundBox.XLength, 40.0, places=6)
        self.assertNotIn("Touched", obj.State)
        figure("part 20 -> 40 long while meshing: left marked for recompute, which meshed it at %g long"
               % obj.FemMesh.BoundBox.XLength)

    def test_11_mesh_joining_an_analysis_gets_material_groups(self):
        # A mesh made before its analysis: recompute after analysis.addObject(mesh) made no
        # <Material>_Volumes groups (nothing touched the mesh), and FreeCAD's CalculiX writer's
        # geometric search gave 3,347 of 5,003 tetrahedra a material.
        import ObjectsFem
        doc = FreeCAD.newDocument("VDMeshLateAnalysis")
        self.addCleanup(close_if_open, doc.Name)
        bf = boolean_fragments(doc, "Late", ("LateLeft", 10, Vector(0, 0, 0)), ("LateRight", 10, Vector(10, 0, 0)))
        obj, info, report, text = meshobject.create_mesh(bf, engine.Parameters(size=3.0))
        deck = obj.OutputFile
        analysis = ObjectsFem.makeAnalysis(doc, "LateAnalysis")
        steel = ObjectsFem.makeMaterialSolid(doc, "LateSteel")
        steel.References = [(bf, "Solid1")]
        analysis.addObject(steel)
        analysis.addObject(obj)
        doc.recompute()

        def volumes(group):
            return set(obj.FemMesh.getGroupElements(femmesh.group_ids(obj.FemMesh)[group]))

        self.assertEqual(volumes(steel.Name + "_Volumes"), volumes("Solid1_Volumes"))
        # a material added to the analysis later: its group on the next recompute too
        alu = ObjectsFem.makeMaterialSolid(doc, "LateAlu")
        alu.References = [(bf, "Solid2")]
        analysis.addObject(alu)
        doc.recompute()
        self.assertEqual(volumes(alu.Name + "_Volumes"), volumes("Solid2_Volumes"))
        self.assertEqual(len(volumes(steel.Name + "_Volumes")) + len(volumes(alu.Name + "_Volumes")),
                         obj.FemMesh.VolumeCount)
        self.assertEqual(obj.OutputFile, deck)  # not meshed again
        figure("mesh added to an analysis after meshing, then a second material: %d + %d of %d tetrahedra "
               "in the materials' groups, not meshed again" % (len(volumes(steel.Name + "_Volumes")),
                                                              len(volumes(alu.Name + "_Volumes")),
                                                              obj.FemMesh.VolumeCount))

    def test_12_part_deleted_or_document_closed_while_meshing(self):
        # The run went on to its end (16 s at size 0.15), then failed with a ReferenceError and left
        # its /tmp/vdmesh-* folder; the panel stayed. Now the run stops (PartGone).
        tmp = self.private_tmpdir()
        for what in ("deleted", "closed"):
            doc = FreeCAD.newDocument("VDMeshGone")
            doc_name = doc.Name
            self.addCleanup(close_if_open, doc_name)
            cut = add_box_with_hole(doc)
            t0, done = time.monotonic(), []

            def idle():
                if not done and time.monotonic() - t0 > 0.5:
                    done.append(time.monotonic())
                    if what == "deleted":
                        doc.removeObject(cut.Name)
                    else:
                        FreeCAD.closeDocument(doc.Name)

            with self.assertRaises(engine.VDMeshError) as ctx:  # was a ReferenceError after the whole run
                meshobject.create_mesh(cut, engine.Parameters(size=0.15), idle=idle)
            self.assertIsInstance(ctx.exception, meshobject.PartGone)
            stopped = time.monotonic() - done[0]
            self.assertLess(stopped, 5.0)
            self.assertEqual(os.listdir(tmp), [])
            if what == "deleted":
                self.assertEqual([o for o in doc.Objects if meshobject.is_vdmesh_object(o)], [])
                FreeCAD.closeDocument(doc_name)
            else:
                self.assertNotIn(doc_name, FreeCAD.listDocuments())
            figure("part %s while meshing: stopped %.2f s later, no folder left" % (what, stopped))

    def test_13_remesh_is_one_undo_step(self):
        # The panel's Remesh opened no transaction: Undo undid the object's creation and deleted it.
        doc, box, obj = meshed_box_with_undo(self, "VDMeshRemeshUndo")
        at3 = obj.FemMesh.VolumeCount
        meshobject.remesh(obj, engine.Parameters(size=5.0))
        at5 = obj.FemMesh.VolumeCount
        self.assertLess(at5, at3)
        # (the first also shows that no other test left FreeCAD's application transaction open:
        # the box would have been recorded under its name)
        self.assertEqual(doc.UndoNames, ["VDMesh remesh", "VDMesh"])
        doc.undo()
        self.assertTrue(meshobject.is_alive(obj))
        self.assertAlmostEqual(obj.Size.Value, 3.0)
        doc.recompute()
        self.assertEqual(obj.FemMesh.VolumeCount, at3)
        figure("remesh 3 -> 5 (%d -> %d tetrahedra), undo: the object stays, Size 3, %d tetrahedra after recompute"
               % (at3, at5, obj.FemMesh.VolumeCount))

    def test_14_failed_create_mesh_without_undo_leaves_document_unchanged(self):
        # freecadcmd's documents record no undo: abortTransaction left the new object in the
        # document and in the analysis when a material named a solid the part does not have.
        import ObjectsFem
        tmp = self.private_tmpdir()
        doc = FreeCAD.newDocument("VDMeshBadMaterial")
        self.addCleanup(close_if_open, doc.Name)
        self.assertEqual(doc.UndoMode, 0)
        box = doc.addObject("Part::Box", "Box")
        doc.recompute()
        analysis = ObjectsFem.makeAnalysis(doc, "Analysis")
        steel = ObjectsFem.makeMaterialSolid(doc, "Steel")
        steel.References = [(box, "Solid2")]
        analysis.addObject(steel)
        doc.recompute()
        names = [o.Name for o in doc.Objects]
        with self.assertRaises(engine.VDMeshError) as ctx:
            meshobject.create_mesh(box, engine.Parameters(size=3.0), analysis=analysis)
        self.assertIn("Solid2", ctx.exception.message)
        self.assertEqual([o.Name for o in doc.Objects], names)
        self.assertEqual(analysis.Group, [steel])
        self.assertEqual(os.listdir(tmp), [])
        figure("material on a missing Solid2, undo off: VDMeshError, document and temporary folder unchanged")

    def test_15_export_to_an_unwritable_path_is_a_vdmesh_error(self):
        # An OSError went through the Export command as a traceback, and no dialog showed.
        doc = FreeCAD.newDocument("VDMeshExportError")
        self.addCleanup(close_if_open, doc.Name)
        box = doc.addObject("Part::Box", "Box")
        doc.recompute()
        obj = meshobject.create_mesh(box, engine.Parameters(size=4.0))[0]
        for name in ("x.inp", "x.msh"):
            path = "/nonexistent-vdmesh-dir/" + name
            with self.assertRaises(engine.VDMeshError) as ctx:
                meshobject.export_mesh(obj, path)
            figure("export to %s: %s" % (path, ctx.exception.message.splitlines()[0]))

    def test_16_errors_name_the_part_not_a_removed_file(self):
        # The program's message named its input, /tmp/vdmesh-.../part.brep, gone by then.
        doc = FreeCAD.newDocument("VDMeshErrorName")
        self.addCleanup(close_if_open, doc.Name)
        bad = doc.addObject("Part::Feature", "OpenSolid")
        bad.Shape = Part.Solid(Part.Shell(Part.makeBox(1, 1, 1).Faces[:5]))
        doc.recompute()
        engines = ["program"] + (["module"] if engine.core_module() is not None else [])
        for name in engines:
            if name == "program":
                os.environ["VDMESH_ENGINE"] = "program"
            try:
                with self.assertRaises(engine.VDMeshError) as ctx:
                    meshobject.create_mesh(bad)
            finally:
                os.environ.pop("VDMESH_ENGINE", None)
            message = ctx.exception.message
            self.assertIn("OpenSolid: Solid1 is not closed", message)
            self.assertNotIn("part.brep", message)
            self.assertNotIn("<brep>", message)
            figure("bad part (%s): %s" % (name, message.splitlines()[-1]))

    def test_17_failed_remesh_changes_nothing(self):
        # A material naming a solid the new mesh lacks raised inside remesh's transaction after the
        # size and the mesh had changed; without undo they stayed changed (a review, 2026-11-30).
        import ObjectsFem
        doc = FreeCAD.newDocument("VDMeshFailedRemesh")
        self.addCleanup(close_if_open, doc.Name)
        box = doc.addObject("Part::Box", "Box")
        doc.recompute()
        obj = meshobject.create_mesh(box, engine.Parameters(size=5.0))[0]
        before, output = obj.FemMesh.VolumeCount, obj.OutputFile
        analysis = ObjectsFem.makeAnalysis(doc, "Analysis")
        steel = ObjectsFem.makeMaterialSolid(doc, "Steel")
        steel.References = [(box, "Solid2")]
        analysis.addObject(steel)
        analysis.addObject(obj)
        with self.assertRaises(engine.VDMeshError) as ctx:
            meshobject.remesh(obj, engine.Parameters(size=3.0))
        self.assertIn("Solid2", ctx.exception.message)
        self.assertAlmostEqual(obj.Size.Value, 5.0)
        self.assertEqual(obj.FemMesh.VolumeCount, before)
        self.assertEqual(obj.OutputFile, output)
        self.assertTrue(os.path.isfile(output))
        figure("remesh refused by a material on Solid2: Size 5, %d tetrahedra and the deck kept" % before)

    def test_18_integer_parameters_mesh_a_current_part(self):
        # Parameters(size=5) against the property's 5.0: the mesh was said to be of a part changed
        # while meshing, left touched, and meshed again at the next recompute.
        doc = FreeCAD.newDocument("VDMeshIntegerSize")
        self.addCleanup(close_if_open, doc.Name)
        box = doc.addObject("Part::Box", "Box")
        doc.recompute()
        obj, info = meshobject.create_mesh(box, engine.Parameters(size=5, sliver_angle=10, ridge_angle=20))[:2]
        self.assertFalse(info["stale"])
        self.assertNotIn("Touched", obj.State)

    def test_19_boss_tangent_to_a_wall(self):
        # A FreeCAD tester's part: a boss whose cylinder touches a wall along a line. FreeCAD's fuse
        # leaves that line in the wall's face as an INTERNAL edge. vdmesh refused the part as "not
        # closed (1 edges bound only one face)"; with that mended, its face refinement threw on the
        # edge (no curve on the boss's face), and every recovery with split vertices on the CAD
        # faces ran away at the line (exit 4, as from the part's STEP export).
        doc = FreeCAD.newDocument("VDMeshTangentBoss")
        self.addCleanup(close_if_open, doc.Name)
        plate = Part.makeBox(60, 60, 5)
        wall = Part.makeBox(60, 5, 25, Vector(0, 40, 0))
        boss = Part.makeCylinder(6, 20, Vector(30, 34, 0))
        shape = plate.fuse([wall, boss]).removeSplitter()
        shape = shape if shape.ShapeType == "Solid" else Part.Solid(shape.Shells[0])
        inner = [e for f in shape.Faces for e in f.Edges if e.Orientation == "Internal"]
        self.assertEqual(len(inner), 1)  # the construction this test is about
        part = doc.addObject("Part::Feature", "TangentBoss")
        part.Shape = shape
        doc.recompute()
        obj, info, report = meshobject.create_mesh(part, engine.Parameters())[:3]
        fm = obj.FemMesh
        self.assertGreater(fm.VolumeCount, 1000)
        self.assertTrue(report["cad"]["planar_splits_fallback"])
        volume = report["cad"]["volumes"][0]
        self.assertLess(abs(volume["mesh"] / shape.Volume - 1), 0.005)
        figure("boss tangent to a wall (INTERNAL edge in the wall): %d tetrahedra, %.3f %% off its volume"
               % (fm.VolumeCount, 100 * (volume["mesh"] / shape.Volume - 1)))

    def test_20_thin_disk_at_the_chosen_size(self):
        # A disk 0.3 thick of radius 25 at Size 0 (vdmesh chooses): its faces get 4 times its mean
        # thickness 2V/A instead of the diagonal / 25 (0.010 deg before), and the panel's summary
        # says so.
        doc = FreeCAD.newDocument("VDMeshThinDisk")
        self.addCleanup(close_if_open, doc.Name)
        part = doc.addObject("Part::Feature", "ThinDisk")
        part.Shape = Part.makeCylinder(25, 0.3)
        doc.recompute()
        obj, info, report = meshobject.create_mesh(part, engine.Parameters())[:3]
        thickness = 2 * part.Shape.Volume / part.Shape.Area
        self.assertEqual(report["cad"]["thin_faces"], 3)
        self.assertAlmostEqual(report["cad"]["thin_size"], 4 * thickness, delta=1e-6 * thickness)
        self.assertGreater(report["quality"]["min_dihedral_deg"], 10)
        self.assertIn("3 faces of a thin part", meshobject.mesh_summary(info, report))
        figure("thin disk (radius 25, 0.3 thick) at the chosen size: %d tetrahedra, smallest dihedral %.2f deg"
               % (obj.FemMesh.VolumeCount, report["quality"]["min_dihedral_deg"]))


def close_if_open(name):
    if name in FreeCAD.listDocuments():
        FreeCAD.closeDocument(name)


def box_shape_object(doc):
    box = doc.addObject("Part::Box", "StoppedBox")
    doc.recompute()
    return box


def physical_names(msh):
    """{(dimension, name)} of a Gmsh file's $PhysicalNames."""
    with open(msh) as f:
        lines = f.read().split("$PhysicalNames\n", 1)[1].split("$EndPhysicalNames", 1)[0].splitlines()
    return {(int(l.split()[0]), l.split(None, 2)[2].strip('"')) for l in lines[1:]}
