// Cells of a uniform grid of cubes, keyed for a hash map: the facet grids of
// the interior candidates (volume/interior_vertices.cpp) and of the cautious
// run's candidate test (volume/facet_takers.cpp).
#pragma once

#include <array>
#include <cmath>
#include <cstdint>

#include "mesh/mesh.h"

namespace vd {

// The integer coordinates of p's cell on a grid of cubes `side` wide.
inline std::array<long, 3> cell_coords(const Vec3& p, double side) {
  return {long(std::floor(p.x / side)), long(std::floor(p.y / side)), long(std::floor(p.z / side))};
}

// A cell's coordinates packed into one key, 21 bits each. They wrap: cells
// 2^21 apart share a key, so what a key lists is tested, not trusted.
inline std::uint64_t pack_cell(const std::array<long, 3>& k) {
  return (std::uint64_t(k[0] & 0x1fffff) << 42) | (std::uint64_t(k[1] & 0x1fffff) << 21) | std::uint64_t(k[2] & 0x1fffff);
}

}  // namespace vd
