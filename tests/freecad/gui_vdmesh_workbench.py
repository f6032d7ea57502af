"""GUI smoke test of the vdmesh workbench under Xvfb (not registered in ctest yet):

    QTWEBENGINE_DISABLE_SANDBOX=1 FREECAD_USER_HOME=/tmp/fchome VDMESH_BIN=$PWD/build/bin/vdmesh \
    VDMESH_GUI_OUT=/tmp/vdmesh-gui xvfb-run -a -s "-screen 0 1600x1000x24" \
    freecad $PWD/tests/freecad/gui_vdmesh_workbench.py -M $PWD/Mod/VDMesh

Activates the workbench, selects a box, runs VDMesh_Mesh, presses Mesh in the task panel and saves
a screenshot of the window; VDMESH_GUI_OUT/result.txt ends with "ok" when every step worked.
"""
import os
import sys, traceback
import FreeCAD, FreeCADGui as Gui
from PySide import QtCore, QtGui
OUT = os.environ.get("VDMESH_GUI_OUT", "/tmp/vdmesh-gui")
os.makedirs(OUT, exist_ok=True)
out = open(os.path.join(OUT, "result.txt"), "w")
def step():
    try:
        Gui.activateWorkbench("VDMeshWorkbench")
        out.write("workbench: %s\n" % Gui.activeWorkbench().name())
        doc = FreeCAD.newDocument("G")
        import Part
        box = doc.addObject("Part::Box", "Box"); doc.recompute()
        Gui.Selection.addSelection(box)
        Gui.runCommand("VDMesh_Mesh")
        dlg = Gui.Control.activeDialog()
        out.write("dialog open: %s\n" % dlg)
        panel = [w for w in QtGui.QApplication.allWidgets() if w.windowTitle() == "vdmesh: tetrahedral mesh"]
        out.write("panel widgets: %d\n" % len(panel))
        # press the Mesh button
        btns = [b for b in QtGui.QApplication.allWidgets() if isinstance(b, QtGui.QPushButton) and b.text() == "Mesh"]
        btns[0].click()
        objs = [o.Name + ":" + o.TypeId for o in doc.Objects]
        out.write("objects: %s\n" % objs)
        Gui.ActiveDocument.ActiveView.viewIsometric(); Gui.SendMsgToActiveView("ViewFit")
        QtGui.QApplication.processEvents()
        QtGui.QApplication.primaryScreen().grabWindow(0).save(os.path.join(OUT, "screenshot.png"))
        out.write("ok\n")
    except Exception:
        out.write(traceback.format_exc())
    out.flush()
    Gui.Control.closeDialog()
    for d in list(FreeCAD.listDocuments()):
        FreeCAD.closeDocument(d)
    Gui.getMainWindow().close()
QtCore.QTimer.singleShot(3000, step)
