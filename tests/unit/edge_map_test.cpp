// The surface adjacency two ways: EdgeFacetPairs sorts its (edge, facet)
// pairs by counting on the edges' lower vertices; whatever the vertex
// numbering, that must be the order std::sort gives the pairs, and EdgeMap
// must list the same facets on every edge.
#include <gtest/gtest.h>

#include <algorithm>
#include <map>
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


// The open-addressed EdgeMap against a std::map through random adds and
// removes: facets on edges of three and more (interfaces) and back, edges
// emptied (the backward-shift deletion) and the table grown from empty.
TEST(EdgeMap, AgreesWithAnOrderedMapThroughAddsAndRemoves) {
  std::mt19937 rng(11);
  std::uniform_int_distribution<int> vertex(0, 40);  // few vertices: shared edges, non-manifold ones
  std::vector<Triangle> facets;
  std::vector<char> present;
  EdgeMap map;
  std::map<std::uint64_t, std::vector<int>> reference;
  auto check = [&] {
    ASSERT_EQ(map.size(), reference.size());
    for (const auto& [key, list] : reference) {
      const auto [a, b] = edge_of_key(key);
      EXPECT_EQ(std::vector<int>(map.facets(a, b)), list) << "edge " << a << "-" << b;
      EXPECT_TRUE(map.contains(b, a));
    }
    size_t seen = 0;
    for (const auto& [key, list] : map.all()) {
      ++seen;
      ASSERT_TRUE(reference.count(key));
      EXPECT_EQ(std::vector<int>(list), reference[key]);
    }
    EXPECT_EQ(seen, reference.size());
    EXPECT_TRUE(map.facets(41, 42).empty());
  };
  for (int step = 0; step < 6000; ++step) {
    const bool removing = step % 3 == 2 || (step > 4000 && step % 3 != 0);
    if (removing && !facets.empty()) {
      const int f = std::uniform_int_distribution<int>(0, static_cast<int>(facets.size()) - 1)(rng);
      if (!present[f]) continue;
      map.remove(f, facets[f]);
      for (int i = 0; i < 3; ++i) {
        auto& l = reference[edge_key(facets[f].v[i], facets[f].v[(i + 1) % 3])];
        l.erase(std::remove(l.begin(), l.end(), f), l.end());
        if (l.empty()) reference.erase(edge_key(facets[f].v[i], facets[f].v[(i + 1) % 3]));
      }
      present[f] = 0;
    } else {
      Triangle t;
      t.v = {vertex(rng), vertex(rng), vertex(rng)};
      if (t.v[0] == t.v[1] || t.v[1] == t.v[2] || t.v[0] == t.v[2]) continue;
      const int f = static_cast<int>(facets.size());
      facets.push_back(t);
      present.push_back(1);
      map.add(f, t);
      for (int i = 0; i < 3; ++i) reference[edge_key(t.v[i], t.v[(i + 1) % 3])].push_back(f);
    }
    if (step % 500 == 0) check();
  }
  check();
  EXPECT_GT(reference.size(), 0u);
  // Every facet gone: the map is empty again.
  for (size_t f = 0; f < facets.size(); ++f)
    if (present[f]) map.remove(static_cast<int>(f), facets[f]);
  EXPECT_EQ(map.size(), 0u);
  size_t left = 0;
  for (const auto& edge : map.all()) left += edge.second.size() + 1;
  EXPECT_EQ(left, 0u);
}

}  // namespace
}  // namespace vd
