// Sliver removal (paper §7), case A: a sliver with two faces on the surface
// (the flat tetrahedra that four nearly coplanar surface vertices make) is
// removed, and its other two faces replace those two facets, under the rules
// of a surface flip: same topological face, same regions, ridge angle under
// the limit. Only slivers against the exterior are removed here; an interface
// sliver would have to change region instead.
#pragma once

#include "mesh/mesh.h"

namespace vd {

struct SliverOptions {
  double sliver_angle_deg = 10.0;  // tetrahedra with a smaller dihedral angle are slivers
  double ridge_angle_deg = 20.0;   // as for flips
};

struct SliverStats {
  long slivers_before = 0;     // tetrahedra under the sliver angle
  long removed_boundary = 0;   // case A
  long slivers_after = 0;
};

SliverStats remove_boundary_slivers(Mesh& m, const SliverOptions& options);

}  // namespace vd
