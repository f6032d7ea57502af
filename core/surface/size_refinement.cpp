#include "surface/size_refinement.h"

#include <algorithm>
#include <cstdint>
#include <limits>
#include <tuple>
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
    // Every (edge, facet) pair, sorted: an edge's facets are one run, in
    // facet order. A hash map of vectors, one allocation per edge and pass,
    // was most of this phase: 0.53 -> 0.13 s on a sphere split to 125k facets.
    std::vector<std::pair<std::uint64_t, int>> pairs;
    pairs.reserve(3 * m.triangles.size());
    for (size_t f = 0; f < m.triangles.size(); ++f)
      for (int e = 0; e < 3; ++e)
        pairs.emplace_back(edge_key(m.triangles[f].v[e], m.triangles[f].v[(e + 1) % 3]), static_cast<int>(f));
    std::sort(pairs.begin(), pairs.end());
    struct LongEdge {
      double length;
      std::uint64_t key;
      size_t first, last;  // its run in `pairs`
      bool operator>(const LongEdge& o) const { return std::tie(length, key) > std::tie(o.length, o.key); }
    };
    std::vector<LongEdge> long_edges;
    for (size_t i = 0, j; i < pairs.size(); i = j) {
      for (j = i + 1; j < pairs.size() && pairs[j].first == pairs[i].first; ++j) {
      }
      const std::uint64_t key = pairs[i].first;
      const int a = static_cast<int>(key >> 32), b = static_cast<int>(key & 0xffffffffu);
      const double l = norm(m.points[a] - m.points[b]);
      if (l > limit(a, b)) long_edges.push_back({l, key, i, j});
    }
    // Longest first, ties by key.
    std::sort(long_edges.begin(), long_edges.end(), std::greater<>());
    std::vector<char> touched(m.triangles.size(), 0);
    for (const LongEdge& edge : long_edges) {
      bool clear = true;
      for (size_t i = edge.first; i < edge.last; ++i) clear = clear && !touched[pairs[i].second];
      if (!clear) {
        again = true;
        continue;
      }
      const std::uint64_t key = edge.key;
      const int a = static_cast<int>(key >> 32), b = static_cast<int>(key & 0xffffffffu);
      const int n = static_cast<int>(m.points.size());
      m.points.push_back(0.5 * (m.points[a] + m.points[b]));
      if (per_vertex) m.point_size.push_back(0.5 * (m.point_size[a] + m.point_size[b]));
      for (size_t i = edge.first; i < edge.last; ++i) {
        const int f = pairs[i].second;
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
