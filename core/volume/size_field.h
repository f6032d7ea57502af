// The mesh size h(x) inside the solid: from --size H, from per-vertex sizes of
// the input, or (default) from the surface's own edge lengths, graded into the
// interior: h grows at most by `gradation` per unit distance, so elements
// grow smoothly away from a fine surface.
#pragma once

#include <vector>

#include "mesh/mesh.h"

namespace vd {

struct SizeFieldOptions {
  double uniform = 0;       // --size H; 0: from the surface only
  double gradation = 0.3;   // largest dh/dx
};

class SizeField {
 public:
  // Built from the surface vertices of `m` (vertices of m.triangles).
  SizeField(const Mesh& m, const SizeFieldOptions& options);
  // From given sizes at the points of m (those <= 0 are left out).
  SizeField(const Mesh& m, const std::vector<double>& vertex_sizes, const SizeFieldOptions& options);
  double at(const Vec3& p) const;
  double smallest() const { return smallest_; }
  // The --size H the field is capped at (0: none, sizes from the surface).
  double requested() const { return uniform_; }

 private:
  // A background grid over the bounding box holds h at its nodes, relaxed by
  // a Dijkstra sweep from the surface vertices; `at` interpolates.
  Vec3 origin_;
  double step_ = 1;
  int n_[3] = {1, 1, 1};
  std::vector<double> h_;
  double uniform_ = 0;
  double smallest_ = 0;
  size_t node_index(int i, int j, int k) const { return (static_cast<size_t>(k) * n_[1] + j) * n_[0] + i; }
};

}  // namespace vd
