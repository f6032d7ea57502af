"""GUI test of the vdmesh workbench (TestVDMeshGui, registered in InitGui.py), under Xvfb:

    QTWEBENGINE_DISABLE_SANDBOX=1 VDMESH_GUI_OUT=/tmp/vdmesh-gui \
    xvfb-run -a -s "-screen 0 1600x1000x24" freecad -t TestVDMeshGui -M /abs/path/Mod/VDMesh

Activates the workbench, selects a box with a hole, runs the VDMesh_Mesh command, sets the size in its
task panel and presses the task view's OK button (TaskView -> MeshTaskPanel.accept: mesh, close);
checks the mesh object; opens it again for editing (the view provider's setEdit), presses Remesh
and saves a screenshot of the window with the panel's report and the mesh in the 3D view into
VDMESH_GUI_OUT (default: a temporary folder) as freecad-workbench.png, and the 3D view alone as
freecad-workbench-3dview.png.
"""
import os
import tempfile
import time
import unittest

import FreeCAD
import FreeCADGui as Gui
from FreeCAD import Vector
from PySide import QtCore, QtGui

from vdmeshwb import femmesh

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
