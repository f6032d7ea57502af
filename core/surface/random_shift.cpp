#include "surface/random_shift.h"

#include <algorithm>
#include <cmath>
#include <optional>
#include <random>

#include "surface/edge_map.h"
#include "surface/face_patches.h"

namespace vd {
namespace {

// A feature edge separates topological faces or regions, is not a plain
// manifold edge, or is a crease; vertices on it may move only along it.
// Moving a vertex of a 90-degree crease "in its tangent plane" would move
// the box's corner off the box.
bool is_feature_edge(const Mesh& m, const FacetList& on_edge, double cos_crease) {
  if (on_edge.size() != 2) return true;
  const Triangle& a = m.triangles[on_edge[0]];
  const Triangle& b = m.triangles[on_edge[1]];
  if (a.face != b.face || std::minmax(a.front, a.back) != std::minmax(b.front, b.back)) return true;
  // Same face and regions: consistently oriented, so the normals compare directly.
  return dot(facet_normal(m.points, a), facet_normal(m.points, b)) < cos_crease;
}

Vec3 random_unit(std::mt19937_64& rng) {
  std::normal_distribution<double> g(0.0, 1.0);
  for (;;) {
    const Vec3 v{g(rng), g(rng), g(rng)};
    if (norm(v) > 1e-12) return normalized(v);
  }
}

}  // namespace

ShiftStats random_shift(Mesh& m, const ShiftOptions& options, const EdgeMap* given) {
  ShiftStats stats;
  const size_t n = m.points.size();
  std::vector<std::vector<int>> vertex_facets(n);
  for (size_t f = 0; f < m.triangles.size(); ++f)
    for (int v : m.triangles[f].v) vertex_facets[v].push_back(static_cast<int>(f));
  std::optional<EdgeMap> own;
  const EdgeMap& edges = given ? *given : own.emplace(m.triangles);

  // Local size: mean length of the incident surface edges, else the given size.
  const std::vector<double> size = surface_vertex_sizes(m, edges);

  const double cos_crease = std::cos(options.crease_angle_deg * M_PI / 180.0);
  std::mt19937_64 rng(options.seed);
  std::uniform_real_distribution<double> unit(0.5, 1.0);
  for (size_t v = 0; v < n; ++v) {
    // Draw for every vertex so that one vertex's kind does not change the
    // numbers the others get.
    const Vec3 direction = random_unit(rng);
    const double magnitude = options.relative * size[v] * unit(rng);
    if (vertex_facets[v].empty()) {
      if (size[v] > 0) {
        m.points[v] = m.points[v] + magnitude * direction;
        ++stats.moved_free;
      } else {
        ++stats.fixed;
      }
      continue;
    }
    // Feature edges at v.
    std::vector<int> feature_ends;
    Vec3 normal{0, 0, 0};
    for (int f : vertex_facets[v]) {
      const Triangle& t = m.triangles[f];
      normal = normal + facet_area(m.points, t) * facet_normal(m.points, t);
      for (int w : t.v)
        if (w != static_cast<int>(v) && is_feature_edge(m, edges.facets(v, w), cos_crease))
          if (std::find(feature_ends.begin(), feature_ends.end(), w) == feature_ends.end())
            feature_ends.push_back(w);
    }
    Vec3 step;
    if (feature_ends.empty()) {
      const Vec3 nrm = normalized(normal);
      step = direction - dot(direction, nrm) * nrm;  // into the tangent plane
      if (norm(step) < 1e-6) {
        ++stats.fixed;
        continue;
      }
      step = magnitude * normalized(step);
    } else if (feature_ends.size() == 2) {
      const Vec3 along = normalized(m.points[feature_ends[1]] - m.points[feature_ends[0]]);
      step = (magnitude * (dot(direction, along) >= 0 ? 1.0 : -1.0)) * along;
    } else {
      ++stats.fixed;  // a corner
      continue;
    }
    // Refuse a move that turns an incident facet over (needles can be thinner
    // than the shift).
    const Vec3 old = m.points[v];
    std::vector<Vec3> before;
    for (int f : vertex_facets[v]) before.push_back(cross(m.points[m.triangles[f].v[1]] - m.points[m.triangles[f].v[0]],
                                                          m.points[m.triangles[f].v[2]] - m.points[m.triangles[f].v[0]]));
    m.points[v] = old + step;
    bool ok = true;
    for (size_t i = 0; i < vertex_facets[v].size() && ok; ++i) {
      const Triangle& t = m.triangles[vertex_facets[v][i]];
      const Vec3 after = cross(m.points[t.v[1]] - m.points[t.v[0]], m.points[t.v[2]] - m.points[t.v[0]]);
      ok = dot(after, before[i]) > 0.5 * dot(before[i], before[i]);
    }
    if (!ok) {
      m.points[v] = old;
      ++stats.fixed;
    } else if (feature_ends.empty()) {
      ++stats.moved_in_plane;
    } else {
      ++stats.moved_on_edge;
    }
  }
  return stats;
}

}  // namespace vd
