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

class EdgeMap {
 public:
  EdgeMap() = default;
  explicit EdgeMap(const std::vector<Triangle>& facets);

  void add(int facet, const Triangle& t);
  void remove(int facet, const Triangle& t);
  // Facets on edge {a, b}; empty when the edge is not on the surface.
  const std::vector<int>& facets(int a, int b) const;
  bool contains(int a, int b) const { return !facets(a, b).empty(); }
  const std::unordered_map<std::uint64_t, std::vector<int>>& all() const { return map_; }

 private:
  std::unordered_map<std::uint64_t, std::vector<int>> map_;
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
