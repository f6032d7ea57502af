# GUI test of the vdmesh workbench, registered in InitGui.py through FreeCAD.__unit_test__:
#     xvfb-run -a -s "-screen 0 1600x1000x24" freecad -t TestVDMeshGui -M /abs/path/Mod/VDMesh
# (as root also QTWEBENGINE_DISABLE_SANDBOX=1); screenshots go to VDMESH_GUI_OUT.
from vdmeshtest.test_gui import TestVDMeshGui  # noqa: F401
