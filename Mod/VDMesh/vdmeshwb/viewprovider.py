"""View provider of the vdmesh mesh object (GUI only): icon, double-click opens the task panel."""
import FreeCADGui

from . import icon


class ViewProviderVDMesh:
    def __init__(self, vobj):
        vobj.Proxy = self

    def attach(self, vobj):
        self.Object = vobj.Object

    def getIcon(self):
        return icon()

    def setEdit(self, vobj, mode=0):
        from . import taskpanel
        FreeCADGui.Control.showDialog(taskpanel.MeshTaskPanel(mesh_object=vobj.Object))
        return True

    def unsetEdit(self, vobj, mode=0):
        FreeCADGui.Control.closeDialog()
        return True

    def doubleClicked(self, vobj):
        if FreeCADGui.Control.activeDialog():
            return False
        vobj.Document.setEdit(vobj.Object.Name)
        return True

    def claimChildren(self):
        return []

    def __getstate__(self):
        return None

    def __setstate__(self, state):
        return None

    def dumps(self):
        return None

    def loads(self, state):
        return None
