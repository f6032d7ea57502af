# vdmesh workbench, application part (runs in freecadcmd too).
# The mesh object and its code live in the vdmeshwb package, importable as soon as FreeCAD has put
# this folder on sys.path; the headless tests (TestVDMeshApp) run with `freecadcmd -t TestVDMeshApp`.
FreeCAD.__unit_test__ += ["TestVDMeshApp"]  # noqa: F821 (FreeCAD's Init namespace)
