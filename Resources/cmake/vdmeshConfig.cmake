# find_package(vdmesh): the targets vdmesh::core (the mesher), vdmesh::converters
# (mesh files by extension) and vdmesh::cad (STEP/IGES/BREP through OpenCASCADE).
# The libraries are static; what they link is found here (GLPK, LZ4 and
# OpenCASCADE by the paths they were built with, Debian 12's).
include(CMakeFindDependencyMacro)
find_dependency(CGAL)
find_dependency(Threads)
find_dependency(ZLIB)
find_dependency(LibLZMA)
include(${CMAKE_CURRENT_LIST_DIR}/vdmeshTargets.cmake)
