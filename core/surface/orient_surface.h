// Orientation for input that has none (TetGen's PLC facets are unoriented):
// facets are turned so that neighbours across manifold edges agree, and each
// connected component so that it encloses a positive volume (normals out).
#pragma once

#include "mesh/mesh.h"

namespace vd {

// Returns the number of facets turned over.
int orient_consistently(Mesh& surface);

}  // namespace vd
