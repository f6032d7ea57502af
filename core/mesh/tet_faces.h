// Faces of tetrahedra and order-free keys of triangles, shared by the steps
// that match tetrahedron faces against surface facets.
#pragma once

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace vd {

// The face of tetrahedron v opposite its vertex i, in the order of v.
inline std::array<int, 3> face_opposite(const std::array<int, 4>& v, int i) {
  std::array<int, 3> f{};
  for (int j = 0, c = 0; j < 4; ++j)
    if (j != i) f[c++] = v[j];
  return f;
}

// The same three vertex ids in increasing order: a key for the triangle
// whatever its orientation.
inline std::array<int, 3> sorted_triple(std::array<int, 3> k) {
  std::sort(k.begin(), k.end());
  return k;
}

// The same for a tetrahedron's four vertex ids.
inline std::array<int, 4> sorted_quad(std::array<int, 4> k) {
  std::sort(k.begin(), k.end());
  return k;
}

// Hashes of those keys for unordered maps.
struct TripleHash {
  size_t operator()(const std::array<int, 3>& k) const {
    return (size_t(k[0]) * 73856093u) ^ (size_t(k[1]) * 19349663u) ^ (size_t(k[2]) * 83492791u);
  }
};
struct QuadHash {
  size_t operator()(const std::array<int, 4>& k) const {
    return (size_t(k[0]) * 73856093u) ^ (size_t(k[1]) * 19349663u) ^ (size_t(k[2]) * 83492791u) ^
           (size_t(k[3]) * 2654435761u);
  }
};

// Facet numbers by their sorted vertex triples, in one open-addressed table:
// a std::unordered_map, a heap node per facet, made the lookups of every
// tetrahedron face a tenth of a surface-only run. For duplicate triples the
// first facet is kept.
class TripleIndex {
 public:
  template <class Facets, class VerticesOf>
  TripleIndex(const Facets& facets, VerticesOf vertices_of) {
    size_t size = 16;
    while (size < 2 * facets.size()) size *= 2;
    slots_.assign(size, Slot{});
    mask_ = size - 1;
    for (size_t f = 0; f < facets.size(); ++f) {
      Slot& s = slot(sorted_triple(vertices_of(facets[f])));
      if (s.facet < 0) s = {sorted_triple(vertices_of(facets[f])), static_cast<int>(f)};
    }
  }
  // The facet with these vertices (any order), or -1.
  int find(const std::array<int, 3>& triple) const { return slot(sorted_triple(triple)).facet; }

 private:
  struct Slot {
    std::array<int, 3> key{-1, -1, -1};
    int facet = -1;
  };
  const Slot& slot(const std::array<int, 3>& k) const {
    std::uint64_t h = static_cast<std::uint32_t>(k[0]);
    h = h * 0x9E3779B97F4A7C15ull + static_cast<std::uint32_t>(k[1]);
    h = h * 0x9E3779B97F4A7C15ull + static_cast<std::uint32_t>(k[2]);
    size_t i = static_cast<size_t>(h ^ (h >> 29)) & mask_;
    while (slots_[i].facet >= 0 && slots_[i].key != k) i = (i + 1) & mask_;
    return slots_[i];
  }
  Slot& slot(const std::array<int, 3>& k) { return const_cast<Slot&>(static_cast<const TripleIndex*>(this)->slot(k)); }
  std::vector<Slot> slots_;
  size_t mask_ = 0;
};

}  // namespace vd
