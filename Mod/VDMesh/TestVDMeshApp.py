# Headless tests of the vdmesh workbench, registered in Init.py through FreeCAD.__unit_test__:
#     freecadcmd -t TestVDMeshApp -M /abs/path/Mod/VDMesh       (or -t TestVDMeshApp.<Class>)
# unittest's loader collects the TestCase classes imported here.
from vdmeshtest.test_mesh import TestVDMeshWorkbench  # noqa: F401
from vdmeshtest.test_second_order import TestVDMeshSecondOrder  # noqa: F401
from vdmeshtest.test_calculix import TestVDMeshCalculix  # noqa: F401
