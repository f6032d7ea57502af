// The paper's advancing-front Delaunay (§6, `--volume advancing-front`): the
// tetrahedra of each region built from its boundary facets inwards, each
// front face closed by the vertex whose sphere through the face holds no
// other vertex on its inner side (gift wrapping). It needs only the vertices
// and the facets, every facet being Delaunay; on vertices in general position
// it gives exactly the Delaunay tetrahedra that the default takes from the
// tetrahedralization (a test compares them).
#pragma once

#include <atomic>
#include <vector>

#include "mesh/mesh.h"

namespace vd {

struct AdvancingFrontStats {
  long front_faces = 0;   // faces taken off the front and closed
  long candidates = 0;    // vertices tested with the exact predicates
  long ties = 0;          // a candidate on the sphere of the best so far (not general position)
  long searches = 0;      // ball searches, counting each growth
};

// The tetrahedra of every region > 0 of `m` (m.points, m.triangles with
// their front/back regions), positively oriented, in the order they were
// made. Throws std::runtime_error when the front cannot close (a front face
// with no vertex on its inner side, or two tetrahedra claiming one side of a
// face): a facet that is not Delaunay, or vertices far from general position.
std::vector<Tetrahedron> advancing_front_tetrahedra(const Mesh& m, AdvancingFrontStats& stats,
                                                   const std::atomic<bool>* cancel = nullptr);

}  // namespace vd
