// Closest-triangle and nearby-triangle queries over a fixed set of triangles
// (CGAL's AABB tree, inexact double arithmetic: its users measure distances
// or name nearby facets, they take no combinatorial decisions from them:
// the checks of `vdmesh compare`, the input facets named in error messages).
#pragma once

#include <array>
#include <limits>
#include <memory>
#include <vector>

#include "mesh/mesh.h"

namespace vd {

class TriangleIndex {
 public:
  // Ids are positions in `triangles`. Triangles of zero area are left out
  // (they have no closest point worth asking about).
  explicit TriangleIndex(const std::vector<std::array<Vec3, 3>>& triangles);
  ~TriangleIndex();
  TriangleIndex(const TriangleIndex&) = delete;
  TriangleIndex& operator=(const TriangleIndex&) = delete;

  bool empty() const;
  struct Hit {
    int id = -1;
    double distance = std::numeric_limits<double>::infinity();
    Vec3 point{0, 0, 0};  // the nearest point of that triangle
  };
  Hit closest(const Vec3& p) const;
  // Ids of the triangles at most `d` from p, replacing `out`.
  void within(const Vec3& p, double d, std::vector<int>& out) const;
  double distance(int id, const Vec3& p) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace vd
