#include "surface/input_surface_geometry.h"

namespace vd {

InputSurfaceGeometry::InputSurfaceGeometry(const Mesh& input, bool faces_given) : faces_given_(faces_given) {
  for (const Triangle& t : input.triangles)
    facets_[t.face].push_back({input.points[t.v[0]], input.points[t.v[1]], input.points[t.v[2]]});
}

std::optional<Vec3> InputSurfaceGeometry::project_onto_face(int face, const Vec3& p, const Vec3&) const {
  auto it = index_.find(face);
  if (it == index_.end()) {
    const auto facets = facets_.find(face);
    if (facets == facets_.end()) return std::nullopt;
    it = index_.emplace(face, std::make_unique<TriangleIndex>(facets->second)).first;
    facets_.erase(facets);
  }
  const TriangleIndex::Hit hit = it->second->closest(p);
  if (hit.id < 0) return std::nullopt;
  return hit.point;
}

}  // namespace vd
