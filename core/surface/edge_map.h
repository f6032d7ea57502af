// Edge-to-facets adjacency of a triangle surface, including non-manifold
// edges (three or more facets on an interface edge) and boundary edges.
#pragma once

#include <cstdint>
#include <unordered_map>
#include <utility>
#include <vector>

#include "mesh/mesh.h"

namespace vd {

// Key of the undirected edge {a, b}.
inline std::uint64_t edge_key(int a, int b) {
  if (a > b) std::swap(a, b);
  return (std::uint64_t(std::uint32_t(a)) << 32) | std::uint32_t(b);
}
inline std::pair<int, int> edge_of_key(std::uint64_t key) {
  return {int(key >> 32), int(key & 0xffffffffu)};
}

// The facets on one edge: two held inline (every manifold edge), all of
// them on the heap past two (interface edges of three or more facets). A
// std::vector per edge was a heap block per edge: a tenth of a bunny's run
// went to building and freeing edge maps.
class FacetList {
 public:
  const int* begin() const { return n_ <= 2 ? small_ : big_.data(); }
  const int* end() const { return begin() + n_; }
  size_t size() const { return static_cast<size_t>(n_); }
  bool empty() const { return n_ == 0; }
  int operator[](size_t i) const { return begin()[i]; }
  operator std::vector<int>() const { return {begin(), end()}; }
  void push_back(int f);
  void erase(int f);  // every occurrence

 private:
  int n_ = 0;
  int small_[2] = {-1, -1};
  std::vector<int> big_;
};

class EdgeMap {
 public:
  EdgeMap() = default;
  explicit EdgeMap(const std::vector<Triangle>& facets);

  void add(int facet, const Triangle& t);
  void remove(int facet, const Triangle& t);
  // Facets on edge {a, b}; empty when the edge is not on the surface.
  const FacetList& facets(int a, int b) const;
  bool contains(int a, int b) const { return !facets(a, b).empty(); }
  const std::unordered_map<std::uint64_t, FacetList>& all() const { return map_; }

 private:
  std::unordered_map<std::uint64_t, FacetList> map_;
};

// Every (edge, facet) pair of a surface, sorted by edge key: an edge's
// facets are one run, in facet order. For passes that rebuild the adjacency
// after each round of changes, where a hash map of vectors (EdgeMap) costs
// an allocation per edge.
struct EdgeFacetPairs {
  std::vector<std::pair<std::uint64_t, int>> pairs;
  explicit EdgeFacetPairs(const std::vector<Triangle>& facets);
  std::vector<int> facets(std::uint64_t key) const;
  bool contains(std::uint64_t key) const;
};

// Local size at each vertex: the mean length of its surface edges, replaced
// by the input's point size where one is given (> 0); 0 for a vertex on no
// edge and without a size.
std::vector<double> surface_vertex_sizes(const Mesh& m, const EdgeMap& edges);

// Does facet t use the directed edge a -> b (in its cyclic order)?
bool has_directed_edge(const Triangle& t, int a, int b);
// The vertex of t that is neither a nor b.
int opposite_vertex(const Triangle& t, int a, int b);

}  // namespace vd
