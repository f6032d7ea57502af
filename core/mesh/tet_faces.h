// Faces of tetrahedra and order-free keys of triangles, shared by the steps
// that match tetrahedron faces against surface facets.
#pragma once

#include <algorithm>
#include <array>
#include <cstddef>

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

}  // namespace vd
