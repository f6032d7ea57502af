"""GUI commands: VDMesh_Mesh, VDMesh_Export, VDMesh_Compare."""
import os

import FreeCAD
import FreeCADGui
from PySide import QtGui

from . import engine, icon, meshobject


def selected_parts():
    """The selected objects with a solid shape (Part, PartDesign Body, compound, BooleanFragments)."""
    out = []
    for o in FreeCADGui.Selection.getSelection():
        shape = getattr(o, "Shape", None)
        if shape is not None and not shape.isNull() and shape.Solids:
            out.append(o)
    return out


def selected_part():
    parts = selected_parts()
    return parts[0] if parts else None


def selected_mesh():
    for o in FreeCADGui.Selection.getSelection():
        if o.isDerivedFrom("Fem::FemMeshObject"):
            return o
    return None


class MeshCommand:
    def GetResources(self):
        return {"Pixmap": icon(), "MenuText": "vdmesh: tetrahedral mesh",
                "ToolTip": "Mesh the selected Part solid, compound or BooleanFragments into a FEM mesh "
                           "with Solid<i> / Face<j> groups (vdmesh, variational Delaunay)"}

    def IsActive(self):
        return FreeCAD.ActiveDocument is not None and selected_part() is not None

    def Activated(self):
        from . import taskpanel
        parts = selected_parts()
        # one mesh per part, as FEM's Gmsh and Netgen meshers; the panel says which are left out
        # nothing selected (a shortcut run past IsActive): the panel asks for a part
        FreeCADGui.Control.showDialog(taskpanel.MeshTaskPanel(part=parts[0] if parts else None, others=parts[1:]))


class ExportCommand:
    def GetResources(self):
        return {"Pixmap": icon(), "MenuText": "vdmesh: export mesh",
                "ToolTip": "Write the selected FEM mesh to Abaqus, Gmsh, VTK/VTU, Medit or TetGen (vdmesh convert)"}

    def IsActive(self):
        return selected_mesh() is not None

    def Activated(self):
        obj = selected_mesh()
        filters = ";;".join(f for f, _ in meshobject.EXPORT_FILTERS)
        path, chosen = QtGui.QFileDialog.getSaveFileName(FreeCADGui.getMainWindow(), "Export mesh",
                                                         obj.Label + ".inp", filters)
        if not path:
            return
        ext = dict(meshobject.EXPORT_FILTERS).get(chosen, ".inp")
        if not os.path.splitext(path)[1]:
            path += ext
        try:
            meshobject.export_mesh(obj, path)
        except (engine.VDMeshError, OSError) as e:  # OSError: the temporary folder, say
            message = e.message if isinstance(e, engine.VDMeshError) else "could not write %s: %s" % (path, e)
            FreeCAD.Console.PrintError("VDMesh export: %s\n" % message)
            QtGui.QMessageBox.critical(FreeCADGui.getMainWindow(), "vdmesh export", message)
            return
        FreeCAD.Console.PrintMessage("VDMesh: %s written\n" % path)


class CompareCommand:
    def GetResources(self):
        return {"Pixmap": icon(), "MenuText": "vdmesh: compare with TetGen",
                "ToolTip": "Mesh the selected part with vdmesh and TetGen and show both columns (vdmesh compare)"}

    def IsActive(self):
        return selected_part() is not None

    def Activated(self):
        part = selected_part()
        from PySide import QtCore
        QtGui.QApplication.setOverrideCursor(QtCore.Qt.WaitCursor)
        try:
            text, result, code = engine.compare_shape(part.Shape)
        except engine.VDMeshError as e:
            QtGui.QApplication.restoreOverrideCursor()
            QtGui.QMessageBox.critical(FreeCADGui.getMainWindow(), "vdmesh compare", e.message)
            return
        QtGui.QApplication.restoreOverrideCursor()
        FreeCAD.Console.PrintMessage("vdmesh compare %s (exit %d):\n%s\n" % (part.Label, code, text))
        dlg = QtGui.QDialog(FreeCADGui.getMainWindow())
        dlg.setWindowTitle("vdmesh compare: %s" % part.Label)
        lay = QtGui.QVBoxLayout(dlg)
        view = QtGui.QPlainTextEdit(text)
        view.setReadOnly(True)
        font = QtGui.QFont("Monospace")
        font.setStyleHint(QtGui.QFont.TypeWriter)
        view.setFont(font)
        lay.addWidget(view)
        dlg.resize(900, 500)
        dlg.show()
        self.dialog = dlg


def register():
    FreeCADGui.addCommand("VDMesh_Mesh", MeshCommand())
    FreeCADGui.addCommand("VDMesh_Export", ExportCommand())
    FreeCADGui.addCommand("VDMesh_Compare", CompareCommand())
    return ["VDMesh_Mesh", "VDMesh_Export", "VDMesh_Compare"]
