# vdmesh workbench, GUI part. Exec'd by FreeCAD without __file__: resources are found through the
# vdmeshwb package (vdmeshwb.icon()).


class VDMeshWorkbench(Workbench):  # noqa: F821 (FreeCAD's InitGui namespace)
    MenuText = "VDMesh"
    ToolTip = "Tetrahedral FEM meshes by vdmesh (variational Delaunay)"

    def __init__(self):
        import vdmeshwb
        self.__class__.Icon = vdmeshwb.icon()

    def Initialize(self):
        from vdmeshwb import commands
        names = commands.register()
        self.appendToolbar("VDMesh", names)
        self.appendMenu("&VDMesh", names)

    def Activated(self):
        pass

    def Deactivated(self):
        pass

    def GetClassName(self):
        return "Gui::PythonWorkbench"


Gui.addWorkbench(VDMeshWorkbench())  # noqa: F821
FreeCAD.__unit_test__ += ["TestVDMeshGui"]  # noqa: F821
