// Pieces shared by the TetGen mesh reader and the .poly/.smesh reader.
#pragma once

#include <string>

#include "io_util.h"

namespace vd::io::detail {

// The path without a TetGen extension (.node .ele .face .poly .smesh).
std::string tetgen_base(const std::string& path);
// Reads a node list ("n 3 attributes markers" then "id x y z ..."); returns
// the first index (0 or 1).
int read_tetgen_nodes(Cursor& in, Mesh& m);
// A node number of the file as a point index; fails when it does not exist.
int tetgen_vertex(Cursor& in, const Mesh& m, int first, const char* what);

}  // namespace vd::io::detail
