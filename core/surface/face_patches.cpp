#include "surface/face_patches.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>

#include "mesh/disjoint_sets.h"
#include "mesh/error.h"
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
  // The facets joined across every smooth manifold edge, each edge looked
  // at once in the map's own order (a walk from each facet looked every
  // edge up twice: a sixteenth of a surface-only run on the bunny).
  DisjointSets patch(m.triangles.size());
  // Past every id given, named or grouped too: a new patch took the name of
  // a face no facet had (2026-11-30).
  int last_given = 0;
  for (const Triangle& t : m.triangles) last_given = std::max(last_given, t.face);
  for (const auto& [face, name] : m.face_names) last_given = std::max(last_given, face);
  for (const auto& [face, groups] : m.face_groups) {
    last_given = std::max(last_given, face);
    for (const int g : groups) last_given = std::max(last_given, g);
  }
  for (const auto& [key, across] : edges.all()) {
    if (across.size() != 2) continue;
    const int f = across[0], g = across[1];
    if (m.triangles[f].face != kNoFace || m.triangles[g].face != kNoFace) continue;
    const auto [a, b] = edge_of_key(key);
    // Facets running the edge the same way are turned over: compare the
    // undirected normals' angle then.
    const bool flipped = has_directed_edge(m.triangles[f], a, b) == has_directed_edge(m.triangles[g], a, b);
    const double c = dot(normal[f], normal[g]) * (flipped ? -1.0 : 1.0);
    if (c < cos_limit) continue;
    patch.join(f, g);
  }
  // Numbered in the order of each patch's first facet.
  std::vector<int> number(m.triangles.size(), 0);
  int patches = 0;
  for (size_t f = 0; f < m.triangles.size(); ++f) {
    if (m.triangles[f].face != kNoFace) continue;
    const int r = patch.find(static_cast<int>(f));
    if (number[r] == 0) {
      if (last_given > std::numeric_limits<int>::max() - 1 - patches)
        throw InputError("face ids up to " + std::to_string(last_given) +
                         " leave no room for the faces of the facets without one");
      number[r] = last_given + ++patches;
    }
    m.triangles[f].face = number[r];
  }
  return patches;
}

}  // namespace vd
