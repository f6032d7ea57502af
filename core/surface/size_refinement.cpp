#include "surface/size_refinement.h"

#include <algorithm>
#include <cstdint>
#include <limits>
#include <unordered_map>
#include <vector>

#include "surface/edge_map.h"

namespace vd {
namespace {

// Replaces facet f = (.., p, q, ..) by the two facets on either side of the
// new vertex n on its edge {p, q}, keeping orientation, face and regions.
void split_facet(Mesh& m, int f, int p, int q, int n) {
  Triangle& t = m.triangles[f];
  int i = 0;
  while (!((t.v[i] == p && t.v[(i + 1) % 3] == q) || (t.v[i] == q && t.v[(i + 1) % 3] == p))) ++i;
  const int a = t.v[i], b = t.v[(i + 1) % 3], c = t.v[(i + 2) % 3];
  Triangle second = t;
  t.v = {a, n, c};
  second.v = {n, b, c};
  m.triangles.push_back(second);
}

}  // namespace

SizeRefinementStats refine_surface_to_size(Mesh& m, double size) {
  SizeRefinementStats stats;
  const bool per_vertex = !m.point_size.empty();
  if (size <= 0 && !per_vertex) return stats;
  auto limit = [&](int a, int b) {
    double h = size > 0 ? size : std::numeric_limits<double>::infinity();
    if (per_vertex && m.point_size[a] > 0 && m.point_size[b] > 0)
      h = std::min(h, 0.5 * (m.point_size[a] + m.point_size[b]));
    return h;
  };
  // Each pass splits every long edge whose facets no earlier split of the
  // pass touched; halving lengths, the passes are logarithmic in size ratio.
  for (bool again = true; again; ++stats.passes) {
    again = false;
    std::unordered_map<std::uint64_t, std::vector<int>> facets_of;
    for (size_t f = 0; f < m.triangles.size(); ++f)
      for (int e = 0; e < 3; ++e)
        facets_of[edge_key(m.triangles[f].v[e], m.triangles[f].v[(e + 1) % 3])].push_back(static_cast<int>(f));
    std::vector<std::pair<double, std::uint64_t>> long_edges;
    for (const auto& [key, facets] : facets_of) {
      const int a = static_cast<int>(key >> 32), b = static_cast<int>(key & 0xffffffffu);
      const double l = norm(m.points[a] - m.points[b]);
      if (l > limit(a, b)) long_edges.emplace_back(l, key);
    }
    // Longest first, ties by key: the order, and so the mesh, does not
    // depend on the hash map's.
    std::sort(long_edges.begin(), long_edges.end(), std::greater<>());
    std::vector<char> touched(m.triangles.size(), 0);
    for (const auto& [len, key] : long_edges) {
      const std::vector<int>& facets = facets_of[key];
      if (std::any_of(facets.begin(), facets.end(), [&](int f) { return touched[f] != 0; })) {
        again = true;
        continue;
      }
      const int a = static_cast<int>(key >> 32), b = static_cast<int>(key & 0xffffffffu);
      const int n = static_cast<int>(m.points.size());
      m.points.push_back(0.5 * (m.points[a] + m.points[b]));
      if (per_vertex) m.point_size.push_back(0.5 * (m.point_size[a] + m.point_size[b]));
      for (int f : facets) {
        split_facet(m, f, a, b, n);
        touched[f] = 1;
      }
      touched.resize(m.triangles.size(), 1);
      ++stats.splits;
      again = true;
    }
  }
  return stats;
}

}  // namespace vd
