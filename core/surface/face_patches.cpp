#include "surface/face_patches.h"

#include <algorithm>
#include <cmath>
#include <optional>

#include "surface/edge_map.h"

namespace vd {

Vec3 facet_area_vector(const std::vector<Vec3>& p, const Triangle& t) {
  return cross(p[t.v[1]] - p[t.v[0]], p[t.v[2]] - p[t.v[0]]);
}

Vec3 facet_normal(const std::vector<Vec3>& p, const Triangle& t) { return normalized(facet_area_vector(p, t)); }

double facet_area(const std::vector<Vec3>& p, const Triangle& t) { return 0.5 * norm(facet_area_vector(p, t)); }

double corner_angle(const Vec3& apex, const Vec3& p, const Vec3& q) {
  const Vec3 a = p - apex, b = q - apex;
  return std::atan2(norm(cross(a, b)), dot(a, b));
}

double smallest_corner_angle(const std::vector<Vec3>& p, const Triangle& t) {
  double best = M_PI;
  for (int i = 0; i < 3; ++i) best = std::min(best, corner_angle(p[t.v[i]], p[t.v[(i + 1) % 3]], p[t.v[(i + 2) % 3]]));
  return best;
}

int assign_face_patches(Mesh& m, double sharp_angle_deg, const EdgeMap* given) {
  std::optional<EdgeMap> own;
  const EdgeMap& edges = given ? *given : own.emplace(m.triangles);
  const double cos_limit = std::cos(sharp_angle_deg * M_PI / 180.0);
  std::vector<Vec3> normal(m.triangles.size());
  for (size_t f = 0; f < m.triangles.size(); ++f) normal[f] = facet_normal(m.points, m.triangles[f]);
  for (Triangle& t : m.triangles) t.face = kNoFace;
  int patches = 0;
  std::vector<int> stack;
  for (size_t seed = 0; seed < m.triangles.size(); ++seed) {
    if (m.triangles[seed].face != kNoFace) continue;
    m.triangles[seed].face = ++patches;
    stack.push_back(static_cast<int>(seed));
    while (!stack.empty()) {
      const int f = stack.back();
      stack.pop_back();
      const Triangle& t = m.triangles[f];
      for (int i = 0; i < 3; ++i) {
        const auto& across = edges.facets(t.v[i], t.v[(i + 1) % 3]);
        if (across.size() != 2) continue;
        const int g = across[0] == f ? across[1] : across[0];
        if (m.triangles[g].face != kNoFace) continue;
        // Facets running the edge the same way are turned over: compare the
        // undirected normals' angle then.
        const bool flipped = has_directed_edge(m.triangles[g], t.v[i], t.v[(i + 1) % 3]);
        const double c = dot(normal[f], normal[g]) * (flipped ? -1.0 : 1.0);
        if (c < cos_limit) continue;
        m.triangles[g].face = patches;
        stack.push_back(g);
      }
    }
  }
  return patches;
}

}  // namespace vd
