// Named groups of triangles (OBJ groups, STL solids) to face ids.
#pragma once

#include <string>
#include <vector>

#include "mesh/mesh.h"

namespace vd::io::detail {

// Face ids for groups named `names` (in file order; groups of one name are
// one face, unnamed ones each their own): the k of names that are all
// "Face<k>" (so our own files read back with their ids), else 1, 2, ... in
// order of first appearance. Names go into m.face_names.
std::vector<int> face_ids_for_groups(const std::vector<std::string>& names, Mesh& m);

}  // namespace vd::io::detail
