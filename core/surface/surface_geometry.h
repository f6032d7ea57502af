// Where a vertex added on the surface goes. The paper splits an edge at its
// mid-point, which is on the chord; on CAD input the true surface is known,
// and a split vertex belongs on the CAD face (or on the CAD edge between two
// faces) so that the mesh follows the geometry. Delaunayzation asks this
// interface; without one, splits stay planar (the paper's behaviour).
#pragma once

#include <optional>
#include <vector>

#include "mesh/mesh.h"

namespace vd {

class SurfaceGeometry {
 public:
  virtual ~SurfaceGeometry() = default;
  // The position of a vertex splitting the surface edge whose facets carry
  // the topological faces `faces` (one entry per facet sharing the edge),
  // given its position `chord` on the straight edge. Returns `chord` when
  // the faces give no better place.
  virtual Vec3 place_on_surface(const std::vector<int>& faces, const Vec3& chord) const = 0;
  // The position of a second-order node on the surface edge (a, b). A node
  // never feeds back into Delaunayzation, so it may always go onto the true
  // geometry where a split vertex sometimes may not. The edge's ends, not
  // only its mid-point, so that the geometry can start its search from them.
  virtual Vec3 place_node(const std::vector<int>& faces, const Vec3& a, const Vec3& b) const {
    return place_on_surface(faces, 0.5 * (a + b));
  }
  // The point of topological face `face` nearest to p, when the face is
  // known and the projection found; `near`, a point of the face near p,
  // where the search starts.
  virtual std::optional<Vec3> project_onto_face(int /*face*/, const Vec3& /*p*/, const Vec3& /*near*/) const {
    return std::nullopt;
  }
  // Each region's true volume by region id, where known (0: unknown).
  virtual std::vector<double> region_volumes() const { return {}; }
  // A face may hold sharp edges: it is a face id of faceted input, not a
  // smooth CAD face.
  virtual bool faces_may_be_sharp() const { return false; }
};

}  // namespace vd
