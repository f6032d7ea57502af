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
// first facet is kept. Most lookups are of tetrahedron faces that are no
// facet, and the table (16 bytes a slot, two slots a facet) outgrows the
// cache: a byte of bits per slot, one set for each facet's hash, answers
// most of those from a sixteenth of the memory, 3 to 6 % of them wrongly
// (the scans over every tetrahedron spent most of their time waiting for
// the table).
class TripleIndex {
 public:
  template <class Facets, class VerticesOf>
  TripleIndex(const Facets& facets, VerticesOf vertices_of) {
    size_t size = 16;
    while (size < 2 * facets.size()) size *= 2;
    slots_.assign(size, Slot{});
    mask_ = size - 1;
    maybe_.assign(size / 8, 0);  // 8 bits per slot
    for (size_t f = 0; f < facets.size(); ++f) {
      const std::array<int, 3> k = sorted_triple(vertices_of(facets[f]));
      const size_t b = bit(k);
      maybe_[b >> 6] |= std::uint64_t{1} << (b & 63);
      Slot& s = slot(k, hash(k));
      if (s.facet < 0) s = {k, static_cast<int>(f)};
    }
  }
  // The facet with these vertices (any order), or -1.
  int find(const std::array<int, 3>& triple) const {
    const size_t b = bit(triple);
    if (!(maybe_[b >> 6] >> (b & 63) & 1)) return -1;
    const std::array<int, 3> k = sorted_triple(triple);
    return slot(k, hash(k)).facet;
  }

 private:
  struct Slot {
    std::array<int, 3> key{-1, -1, -1};
    int facet = -1;
  };
  static std::uint64_t hash(const std::array<int, 3>& k) {
    std::uint64_t h = static_cast<std::uint32_t>(k[0]);
    h = h * 0x9E3779B97F4A7C15ull + static_cast<std::uint32_t>(k[1]);
    h = h * 0x9E3779B97F4A7C15ull + static_cast<std::uint32_t>(k[2]);
    return h;
  }
  // The bit comes from a hash of its own that does not depend on the order
  // of the three ids, so that most lookups are answered without sorting
  // them (branches the processor cannot foresee).
  size_t bit(const std::array<int, 3>& k) const {
    auto mix = [](int x) {
      const std::uint64_t h = static_cast<std::uint32_t>(x) * 0xD6E8FEB86659FD93ull;
      return h ^ (h >> 32);
    };
    const std::uint64_t h = (mix(k[0]) + mix(k[1]) + mix(k[2])) * 0x9E3779B97F4A7C15ull;
    return static_cast<size_t>(h >> 32) & (mask_ * 8 + 7);
  }
  const Slot& slot(const std::array<int, 3>& k, std::uint64_t h) const {
    size_t i = static_cast<size_t>(h ^ (h >> 29)) & mask_;
    while (slots_[i].facet >= 0 && slots_[i].key != k) i = (i + 1) & mask_;
    return slots_[i];
  }
  Slot& slot(const std::array<int, 3>& k, std::uint64_t h) {
    return const_cast<Slot&>(static_cast<const TripleIndex*>(this)->slot(k, h));
  }
  std::vector<Slot> slots_;
  std::vector<std::uint64_t> maybe_;  // 8 bits per slot
  size_t mask_ = 0;
};

}  // namespace vd
