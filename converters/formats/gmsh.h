// Gmsh MSH 2.2 and 4.1 (ASCII and binary): what the reader and writer share.
#pragma once

#include <string>

#include "mesh/mesh.h"

namespace vd::io::detail {

Mesh read_gmsh(const std::string& path);

// Element types vdmesh keeps.
constexpr int kMshTriangle = 2, kMshTet = 4, kMshTriangle6 = 9, kMshTet10 = 11;

// Nodes per element for Gmsh element types 1..31 (the fixed-size ones);
// -1 for a type this table does not know.
int msh_nodes_per_element(int type);

// Gmsh numbers the last two edges of the 10-node tetrahedron (23, 13), vdmesh
// and VTK (13, 23): the same swap converts both ways.
inline void swap_tet10_gmsh(TetMidNodes& mid) { std::swap(mid[4], mid[5]); }

}  // namespace vd::io::detail
