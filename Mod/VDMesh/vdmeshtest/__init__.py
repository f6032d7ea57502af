"""Tests of the vdmesh workbench, run by FreeCAD's test runner:

    freecadcmd -t TestVDMeshApp -M /abs/path/Mod/VDMesh          headless (mesh, second order, CalculiX)
    xvfb-run -a freecad -t TestVDMeshGui -M /abs/path/Mod/VDMesh  GUI (Mesh command, task panel, screenshot)

The vdmesh program is found as the workbench finds it (VDMESH_BIN, PATH, preference).
"""
