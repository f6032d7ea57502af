// The surface adjacency two ways: EdgeFacetPairs sorts its (edge, facet)
// pairs by counting on the edges' lower vertices; whatever the vertex
// numbering, that must be the order std::sort gives the pairs, and EdgeMap
// must list the same facets on every edge.
#include <gtest/gtest.h>

#include <algorithm>
#include <numeric>
#include <random>

#include "mesh/shapes.h"
#include "surface/edge_map.h"

namespace vd {
namespace {

std::vector<std::pair<std::uint64_t, int>> sorted_pairs(const std::vector<Triangle>& facets) {
  std::vector<std::pair<std::uint64_t, int>> out;
  for (size_t f = 0; f < facets.size(); ++f)
    for (int i = 0; i < 3; ++i) out.emplace_back(edge_key(facets[f].v[i], facets[f].v[(i + 1) % 3]), static_cast<int>(f));
  std::sort(out.begin(), out.end());
  return out;
}

// A closed cone: vertex 0 the apex of `n` facets (so the lowest id of all
// their edges to it, a run longer than the short-run sort takes), the rim
// closed by a fan from vertex 1, the centre of the base.
std::vector<Triangle> cone(int n) {
  std::vector<Triangle> t;
  for (int i = 0; i < n; ++i) {
    const int a = 2 + i, b = 2 + (i + 1) % n;
    t.push_back({{0, a, b}});
    t.push_back({{1, b, a}});
  }
  return t;
}

void expect_both_agree(const std::vector<Triangle>& facets) {
  const EdgeFacetPairs pairs(facets);
  EXPECT_EQ(pairs.pairs, sorted_pairs(facets));
  const EdgeMap map(facets);
  for (size_t i = 0; i < pairs.pairs.size();) {
    const std::uint64_t key = pairs.pairs[i].first;
    const auto [a, b] = edge_of_key(key);
    std::vector<int> from_map = map.facets(a, b);
    std::sort(from_map.begin(), from_map.end());
    EXPECT_EQ(pairs.facets(key), from_map) << "edge " << a << "-" << b;
    while (i < pairs.pairs.size() && pairs.pairs[i].first == key) ++i;
  }
}

TEST(EdgeFacetPairs, SortedAsStdSortOnASphereNumberedAnyhow) {
  Mesh m = shapes::icosphere({0, 0, 0}, 1.0, 3);
  expect_both_agree(m.triangles);
  // The same surface with its vertices numbered at random: the runs by
  // lower vertex are then of every length.
  std::vector<int> id(m.points.size());
  std::iota(id.begin(), id.end(), 0);
  std::shuffle(id.begin(), id.end(), std::mt19937(7));
  for (Triangle& t : m.triangles)
    for (int& v : t.v) v = id[static_cast<size_t>(v)];
  expect_both_agree(m.triangles);
}

TEST(EdgeFacetPairs, SortedAsStdSortAroundAVertexOfManyEdges) {
  expect_both_agree(cone(7));
  expect_both_agree(cone(100));  // 200 pairs on vertex 0, 200 on vertex 1
}

}  // namespace
}  // namespace vd
