"""vdmesh FreeCAD workbench: tetrahedral FEM meshes of Part solids by the vdmesh mesher.

Modules:
  engine      mesh and convert through the `vdmesh` Python module, else the program; compare; errors with exit codes
  inpreader   read vdmesh's Abaqus deck (*NODE, C3D4 per *ELSET, *SURFACE / *NSET per face)
  femmesh     build a Fem.FemMesh with Solid<i> / Face<j> groups from it
  meshobject  the Fem::FemMeshObjectPython object (parameters as properties, recomputable)
  commands    GUI commands (Mesh, Export, Compare with TetGen); taskpanel: the Mesh task panel
"""
import os

RESOURCES = os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "Resources")
ICONS = os.path.join(RESOURCES, "icons")


def icon(name="VDMesh.svg"):
    return os.path.join(ICONS, name)
