// Edge-to-facets adjacency of a triangle surface, including non-manifold
// edges (three or more facets on an interface edge) and boundary edges.
#pragma once

#include <cstdint>
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

// The facets on one edge, in the order they were added: a copy for one
// or two facets (every manifold edge), a view of the map's list past two
// (interface edges of three or more facets), valid until that edge changes.
class FacetList {
 public:
  FacetList() = default;
  const int* begin() const { return n_ <= 2 ? small_ : big_; }
  const int* end() const { return begin() + n_; }
  size_t size() const { return static_cast<size_t>(n_); }
  bool empty() const { return n_ == 0; }
  int operator[](size_t i) const { return begin()[i]; }
  operator std::vector<int>() const { return {begin(), end()}; }

 private:
  friend class EdgeMap;
  int n_ = 0;
  int small_[2] = {-1, -1};
  const int* big_ = nullptr;
};

// Edge -> facets, in one open-addressed table (linear probing, deletion by
// backward shift). A std::unordered_map of lists made a heap node per edge:
// on gmsh_simple_plane.brep its lookups and inserts were the largest share
// of our own code in a profile (258 of 4,031 samples, 2026-11-28), and the
// CAD refinement builds a map per pass. Its order of iteration was also
// the standard library's; this one's follows from our hash and the order
// of insertion only, so sums over all() come out the same everywhere.
class EdgeMap {
 public:
  EdgeMap() = default;
  explicit EdgeMap(const std::vector<Triangle>& facets);

  void add(int facet, const Triangle& t);
  void remove(int facet, const Triangle& t);
  // Facets on edge {a, b}; empty when the edge is not on the surface.
  FacetList facets(int a, int b) const;
  bool contains(int a, int b) const { return find(edge_key(a, b)) != kNone; }
  size_t size() const { return size_; }

  // Every edge with its facets, as (key, FacetList) pairs in table order.
  class Iterator {
   public:
    Iterator(const EdgeMap& map, size_t slot) : map_(&map), slot_(slot) { skip_empty(); }
    std::pair<std::uint64_t, FacetList> operator*() const {
      return {map_->slots_[slot_].key, map_->list(map_->slots_[slot_])};
    }
    Iterator& operator++() {
      ++slot_;
      skip_empty();
      return *this;
    }
    bool operator!=(const Iterator& o) const { return slot_ != o.slot_; }

   private:
    void skip_empty() {
      while (slot_ < map_->slots_.size() && map_->slots_[slot_].key == kEmpty) ++slot_;
    }
    const EdgeMap* map_;
    size_t slot_;
  };
  struct Edges {
    const EdgeMap* map;
    Iterator begin() const { return {*map, 0}; }
    Iterator end() const { return {*map, map->slots_.size()}; }
    size_t size() const { return map->size_; }
  };
  Edges all() const { return {this}; }

 private:
  static constexpr std::uint64_t kEmpty = ~std::uint64_t{0};  // no edge has this key
  static constexpr size_t kNone = ~size_t{0};
  struct Slot {
    std::uint64_t key = kEmpty;
    int n = 0;     // facets on the edge
    int a = -1;    // the first facet; past two, the index of the list in big_
    int b = -1;    // the second facet
  };

  size_t home(std::uint64_t key) const {
    return static_cast<size_t>((key * 0x9E3779B97F4A7C15ull) >> shift_);
  }
  size_t find(std::uint64_t key) const;
  Slot& find_or_insert(std::uint64_t key);
  void erase_slot(size_t i);
  void empty_slots(size_t at_least);
  void grow();
  FacetList list(const Slot& s) const;
  void push(Slot& s, int facet);
  void erase(Slot& s, int facet);  // every occurrence

  std::vector<Slot> slots_;
  int shift_ = 64;
  size_t size_ = 0;
  std::vector<std::vector<int>> big_;  // lists of three or more facets
  std::vector<int> free_big_;          // their unused indices
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
