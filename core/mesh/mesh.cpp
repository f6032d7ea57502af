#include "mesh/mesh.h"

#include <cmath>

namespace vd {

double norm(Vec3 a) { return std::sqrt(dot(a, a)); }

Vec3 normalized(Vec3 a) {
  const double n = norm(a);
  return n > 0 ? (1.0 / n) * a : a;
}

bool Mesh::has_region_tags() const {
  for (const Triangle& t : triangles)
    if (t.front == kUnknownRegion || t.back == kUnknownRegion) return false;
  return !triangles.empty();
}

bool Mesh::has_face_tags() const {
  for (const Triangle& t : triangles)
    if (t.face == kNoFace) return false;
  return !triangles.empty();
}

}  // namespace vd
