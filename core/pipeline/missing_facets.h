// Where a stopped recovery left its missing facets, in words: a count of
// facets is no help to someone who has to change the model or the options.
#pragma once

#include <string>
#include <vector>

#include "mesh/mesh.h"

namespace vd {

// The places where most missing facets gather (up to three, each with its
// count and centre) and the faces with the most of them (by name when the
// surface names its faces: "Face60"), e.g. "most of them near (0.471,
// 0.0318, 0) (87,281) and (0.291, 0.0318, 0) (82,463); faces Face60
// (40,112), Face68 (39,870)".
std::string where_facets_are_missing(const Mesh& m, const std::vector<int>& missing);

}  // namespace vd
