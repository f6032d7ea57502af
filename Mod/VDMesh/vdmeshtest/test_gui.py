"""GUI test of the vdmesh workbench (TestVDMeshGui, registered in InitGui.py), under Xvfb:

    QTWEBENGINE_DISABLE_SANDBOX=1 VDMESH_GUI_OUT=/tmp/vdmesh-gui \
    xvfb-run -a -s "-screen 0 1600x1000x24" freecad -t TestVDMeshGui -M /abs/path/Mod/VDMesh

Activates the workbench, selects a box with a hole, runs the VDMesh_Mesh command, sets the size in its
task panel and presses the task view's OK button (TaskView -> MeshTaskPanel.accept: mesh, close);
checks the mesh object; opens it again for editing (the view provider's setEdit), presses Remesh
and saves a screenshot of the window with the panel's report and the mesh in the 3D view into
VDMESH_GUI_OUT (default: a temporary folder) as freecad-workbench.png, and the 3D view alone as
freecad-workbench-3dview.png. Then the panel's other paths: OK in edit mode applies a changed size,
Remesh is one undo step, two selected parts are said, an unwritable export path shows a dialog, and
closing the document or deleting the part while meshing stops the run and closes the panel; when
no run is on, closing the document or deleting the part or the mesh closes the panel.
"""
import os
import shutil
import tempfile
import time
import unittest

import FreeCAD
import FreeCADGui as Gui
from FreeCAD import Vector
from PySide import QtCore, QtGui

from vdmeshwb import engine, femmesh, meshobject

from .support import figure, print_figures

SIZE = 1.0


def process_events(seconds=0.3):
    """Lets Qt and Coin draw (the 3D view repaints from the event loop). A polling loop: a nested
    QEventLoop quit by a single-shot timer sometimes never returned under FreeCAD's test runner."""
    end = time.time() + seconds
    while time.time() < end:
        QtGui.QApplication.processEvents(QtCore.QEventLoop.AllEvents, 50)
        time.sleep(0.02)


def task_panel():
    forms = [w for w in QtGui.QApplication.allWidgets() if w.objectName() == "VDMeshTaskPanel" and w.isVisible()]
    return forms[0] if len(forms) == 1 else None


def click_task_view_button(which):
    """Presses the task view's standard button (OK, Close) as a user would; False when there is none.
    Found and clicked in one go: PySide2 drops the button's wrapper once the list of all widgets is
    gone."""
    widgets = QtGui.QApplication.allWidgets()
    for box in widgets:
        if isinstance(box, QtGui.QDialogButtonBox) and box.isVisible():
            b = box.button(which)
            if b is not None and b.isVisible():
                b.click()
                return True
    return False


def distinct_colours(image, step=4):
    colours = set()
    for y in range(0, image.height(), step):
        for x in range(0, image.width(), step):
            colours.add(image.pixel(x, y))
    return colours


class TestVDMeshGui(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.out = os.environ.get("VDMESH_GUI_OUT") or tempfile.mkdtemp(prefix="vdmesh-gui-")
        os.makedirs(cls.out, exist_ok=True)
        mw = Gui.getMainWindow()
        mw.resize(1600, 1000)
        mw.showMaximized()
        Gui.activateWorkbench("VDMeshWorkbench")  # registers the commands, whichever test runs first

    @classmethod
    def tearDownClass(cls):
        print_figures("TestVDMeshGui", "gui")

    def tearDown(self):
        if Gui.Control.activeDialog():
            Gui.Control.closeDialog()
        for name in list(FreeCAD.listDocuments()):
            FreeCAD.closeDocument(name)

    def box_with_hole(self, doc):
        import Part
        shape = Part.makeBox(10, 10, 4, Vector(-5, -5, 0)).cut(Part.makeCylinder(2, 6, Vector(0, 0, -1)))
        part = doc.addObject("Part::Feature", "BoxWithHole")
        part.Shape = shape.Solids[0]
        doc.recompute()
        return part

    def mesh_panel_on_a_box(self, doc):
        """A box with a hole in doc, selected, and the Mesh command's panel open on it: (part, form)."""
        part = self.box_with_hole(doc)
        Gui.Selection.clearSelection()
        Gui.Selection.addSelection(part)
        Gui.runCommand("VDMesh_Mesh")
        process_events()
        return part, task_panel()

    def test_mesh_command_task_panel_screenshot(self):
        Gui.activateWorkbench("VDMeshWorkbench")
        self.assertEqual(Gui.activeWorkbench().name(), "VDMeshWorkbench")
        doc = FreeCAD.newDocument("VDMeshGui")
        part = self.box_with_hole(doc)
        Gui.Selection.clearSelection()
        Gui.Selection.addSelection(part)

        # the command opens the task panel; the task view's OK meshes and closes it
        Gui.runCommand("VDMesh_Mesh")
        process_events()
        self.assertTrue(Gui.Control.activeDialog())
        form = task_panel()
        self.assertIsNotNone(form, "the VDMesh task panel is not shown")
        form.findChild(QtGui.QDoubleSpinBox, "size").setValue(SIZE)
        self.assertTrue(click_task_view_button(QtGui.QDialogButtonBox.Ok), "no OK button in the task view")
        process_events()
        self.assertFalse(Gui.Control.activeDialog(), "OK should mesh and close the panel")
        meshes = [o for o in doc.Objects if o.TypeId == "Fem::FemMeshObjectPython"]
        self.assertEqual(len(meshes), 1)
        obj = meshes[0]
        self.assertIs(obj.Part, part)
        self.assertAlmostEqual(obj.Size.Value, SIZE)
        fm = obj.FemMesh
        self.assertGreater(fm.VolumeCount, 1000)
        self.assertTrue(all(len(fm.getElementNodes(e)) == 4 for e in fm.Volumes[:100]))
        groups = femmesh.group_ids(fm)
        self.assertIn("Solid1_Volumes", groups)
        self.assertEqual(len([g for g in groups if g.endswith("_Faces")]), len(part.Shape.Faces))
        self.assertIsNotNone(obj.ViewObject.Proxy, "the mesh object has no view provider proxy")
        figure("Mesh command, OK in the task panel: %d nodes, %d tetrahedra, %d groups"
               % (fm.NodeCount, fm.VolumeCount, len(groups)), "gui")

        # edit the mesh object (what a double click does), Remesh: the report shows in the panel
        part.ViewObject.Visibility = False
        Gui.ActiveDocument.setEdit(obj.Name)
        process_events()
        form = task_panel()
        self.assertIsNotNone(form, "setEdit did not open the VDMesh task panel")
        self.assertAlmostEqual(form.findChild(QtGui.QDoubleSpinBox, "size").value(), SIZE)
        form.findChild(QtGui.QPushButton, "run").click()
        process_events()
        report = form.findChild(QtGui.QPlainTextEdit, "report").toPlainText()
        self.assertIn("tetrahedra", report)
        self.assertIn("dihedral angles", report)
        view = Gui.ActiveDocument.ActiveView
        view.viewIsometric()
        view.fitAll()
        process_events(1.0)

        shot = os.path.join(self.out, "freecad-workbench.png")
        screen = QtGui.QApplication.primaryScreen().grabWindow(0)
        self.assertTrue(screen.save(shot))
        image = QtGui.QImage(shot)
        self.assertGreaterEqual(image.width(), 800)
        self.assertGreater(len(distinct_colours(image)), 50, "the screenshot looks blank")
        view_shot = os.path.join(self.out, "freecad-workbench-3dview.png")
        view.saveImage(view_shot, 800, 600, "White")
        colours = distinct_colours(QtGui.QImage(view_shot), 2)
        self.assertGreater(len(colours), 10, "the 3D view shows nothing but the background")
        figure("screenshot %s (%dx%d, %d colours); 3D view %s (%d colours)"
               % (shot, image.width(), image.height(), len(distinct_colours(image)), view_shot, len(colours)), "gui")

        Gui.Control.closeDialog()
        Gui.ActiveDocument.resetEdit()
        process_events()

    def mesh_object(self, doc, size=2.0):
        return meshobject.create_mesh(self.box_with_hole(doc), engine.Parameters(size=size))[0]

    def test_edit_ok_applies_and_remesh_undoes(self):
        # OK in edit mode closed the panel and dropped a changed Size; Remesh opened no transaction,
        # and Undo deleted the mesh object (it undid its creation).
        doc = FreeCAD.newDocument("VDMeshGuiEdit")
        obj = self.mesh_object(doc)
        at2 = obj.FemMesh.VolumeCount
        Gui.ActiveDocument.setEdit(obj.Name)
        process_events()
        task_panel().findChild(QtGui.QDoubleSpinBox, "size").setValue(1.5)
        self.assertTrue(click_task_view_button(QtGui.QDialogButtonBox.Ok))
        process_events()
        self.assertFalse(Gui.Control.activeDialog())
        self.assertAlmostEqual(obj.Size.Value, 1.5)
        at15 = obj.FemMesh.VolumeCount
        self.assertGreater(at15, at2)
        undo_steps = len(doc.UndoNames)

        Gui.ActiveDocument.setEdit(obj.Name)
        process_events()
        form = task_panel()
        form.findChild(QtGui.QDoubleSpinBox, "size").setValue(3.0)
        form.findChild(QtGui.QPushButton, "run").click()
        process_events()
        self.assertTrue(click_task_view_button(QtGui.QDialogButtonBox.Close))
        process_events()
        self.assertAlmostEqual(obj.Size.Value, 3.0)
        self.assertEqual(len(doc.UndoNames), undo_steps + 1)
        self.assertEqual(doc.UndoNames[0], "VDMesh remesh")
        Gui.runCommand("Std_Undo")
        process_events()
        self.assertTrue(meshobject.is_alive(obj), "Undo deleted the mesh object")
        self.assertAlmostEqual(obj.Size.Value, 1.5)
        doc.recompute()
        self.assertEqual(obj.FemMesh.VolumeCount, at15)
        figure("edit, Size 2 -> 1.5, OK: %d -> %d tetrahedra; Remesh at 3, Undo: Size 1.5, %d tetrahedra"
               % (at2, at15, obj.FemMesh.VolumeCount), "gui")

    def test_two_selected_parts_are_said(self):
        # BoxB was left out without a word.
        doc = FreeCAD.newDocument("VDMeshGuiTwo")
        a, b = doc.addObject("Part::Box", "BoxA"), doc.addObject("Part::Box", "BoxB")
        b.Placement.Base = Vector(50, 0, 0)
        doc.recompute()
        Gui.Selection.clearSelection()
        Gui.Selection.addSelection(a)
        Gui.Selection.addSelection(b)
        Gui.runCommand("VDMesh_Mesh")
        process_events()
        form = task_panel()
        status = form.findChild(QtGui.QLabel, "status").text()
        self.assertIn("only BoxA is meshed", status)
        self.assertIn("BoxB", status)
        figure("two parts selected: %s" % QtGui.QTextDocumentFragment.fromHtml(status).toPlainText(), "gui")

    def test_export_error_shows_a_dialog(self):
        # An unwritable path gave a traceback in the report view and no dialog.
        doc = FreeCAD.newDocument("VDMeshGuiExport")
        obj = self.mesh_object(doc, 4.0)
        shown = []
        path = "/nonexistent-vdmesh-dir/x.inp"
        for cls, name, fake in ((QtGui.QFileDialog, "getSaveFileName", lambda *a, **k: (path, "")),
                                (QtGui.QMessageBox, "critical", lambda *a, **k: shown.append(a[2]))):
            self.addCleanup(setattr, cls, name, getattr(cls, name))
            setattr(cls, name, staticmethod(fake))
        Gui.Selection.clearSelection()
        Gui.Selection.addSelection(obj)
        Gui.runCommand("VDMesh_Export")
        process_events()
        self.assertEqual(len(shown), 1)
        self.assertIn(path, shown[0])
        figure("export to an unwritable path: dialog says %r" % shown[0], "gui")

    def test_document_closed_or_part_deleted_while_meshing(self):
        # The run went on (16 s), then a ReferenceError; the panel stayed ("meshing ... (Stop
        # cancels)" for a closed document) and the run's /tmp/vdmesh-* folder too.
        tmp = tempfile.mkdtemp(prefix="vdmesh-fc-tmpdir-")
        self.addCleanup(shutil.rmtree, tmp, True)
        self.addCleanup(setattr, tempfile, "tempdir", tempfile.tempdir)
        tempfile.tempdir = tmp
        for mode in ("close", "delete"):
            doc = FreeCAD.newDocument("VDMeshGuiGone")
            part, form = self.mesh_panel_on_a_box(doc)
            form.findChild(QtGui.QDoubleSpinBox, "size").setValue(0.15)  # 16 s to the end
            name = doc.Name

            def act():
                if mode == "close":
                    FreeCAD.closeDocument(name)
                else:
                    doc.removeObject(part.Name)
                    doc.recompute()

            QtCore.QTimer.singleShot(800, act)
            t = time.time()
            form.findChild(QtGui.QPushButton, "run").click()
            seconds = time.time() - t
            process_events()
            self.assertFalse(Gui.Control.activeDialog(), "the panel stayed (%s)" % mode)
            self.assertLess(seconds, 6.0)
            self.assertEqual(os.listdir(tmp), [])
            if mode == "delete":
                self.assertEqual([o.Name for o in doc.Objects], [])
            figure("%s while meshing: run stopped, panel closed %.1f s after Mesh, no folder left" % (mode, seconds),
                   "gui")

    def test_document_closed_or_part_deleted_while_idle(self):
        # The panel stayed open on a closed document, and Mesh then raised a ReferenceError from the
        # deleted part (FreeCAD closes no task dialog of a document it closes).
        for mode in ("close", "delete", "delete the mesh made"):
            doc = FreeCAD.newDocument("VDMeshGuiIdle")
            part, form = self.mesh_panel_on_a_box(doc)
            self.assertIsNotNone(form)
            self.addCleanup(lambda name=doc.Name: name in FreeCAD.listDocuments() and FreeCAD.closeDocument(name))
            # The Model tab shown, as when the part is deleted in the tree: the panel is then hidden.
            combo = [w for w in QtGui.QApplication.allWidgets() if isinstance(w, QtGui.QTabWidget)
                     and w.objectName() == "combiTab"]
            self.assertEqual(len(combo), 1)
            combo[0].setCurrentIndex(0)
            process_events()
            self.assertFalse(form.isVisible())  # what the panel's first watcher took for closed
            if mode == "close":
                FreeCAD.closeDocument(doc.Name)
            elif mode == "delete":
                doc.removeObject(part.Name)
                doc.recompute()
            else:
                form.findChild(QtGui.QDoubleSpinBox, "size").setValue(3.0)
                form.findChild(QtGui.QPushButton, "run").click()
                process_events()
                meshes = [o for o in doc.Objects if meshobject.is_vdmesh_object(o)]
                self.assertEqual(len(meshes), 1)
                self.assertTrue(Gui.Control.activeDialog())
                doc.removeObject(meshes[0].Name)
                doc.recompute()
            process_events()
            self.assertFalse(Gui.Control.activeDialog(), "the panel stayed (%s)" % mode)
            figure("%s while the panel is open: panel closed" % mode, "gui")
