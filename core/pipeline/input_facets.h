// The facets of the input that facets of a changed surface came from: an
// error found after the refinement to a size or recovery's splits names the
// facets of the file the user has, not of a surface they never saw.
#pragma once

#include <vector>

#include "mesh/mesh.h"

namespace vd {

// The facets of `input` under `facets` (indices into changed.triangles):
// those nearest each one's centroid and a point towards each of its corners
// (splits keep a facet's pieces on it; a facet flipped within a face lies on
// the two it was flipped from), ascending and without repeats.
std::vector<int> input_facets_under(const Mesh& input, const Mesh& changed, const std::vector<int>& facets);

}  // namespace vd
