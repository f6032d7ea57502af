// Faces of tetrahedra and order-free keys of triangles, shared by the steps
// that match tetrahedron faces against surface facets.
#pragma once

#include <algorithm>
#include <array>

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

}  // namespace vd
