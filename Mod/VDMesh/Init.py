# vdmesh workbench, application part (runs in freecadcmd too).
# Nothing to register without the GUI: the mesh object and its code live in the vdmeshwb package,
# importable as soon as FreeCAD has put this folder on sys.path.
