// Surface edges brought down to the requested size before Delaunayzation.
// Delaunayzation splits only what is not Delaunay: a 10 x 1 box given as 12
// triangles stays 12 triangles, and with `--size 0.5` the interior vertices
// then meet facets fifty times their size, which makes tetrahedra no solver
// can use. So with a size given (--size, or sizes per input vertex), every
// surface edge longer than the size there is split at its mid-point, longest
// first, in every facet that shares it. The mid-point lies on the input
// facets, so the surface keeps its exact shape (CAD input is refined on the
// CAD geometry instead, in core/cad).
#pragma once

#include "mesh/mesh.h"

namespace vd {

struct SizeRefinementStats {
  int splits = 0;      // edges split
  int passes = 0;
};

// `size` > 0: the largest edge length everywhere; per-vertex sizes in
// m.point_size (when given, > 0) lower it locally (mean of the two ends).
// Nothing to do when neither is given.
SizeRefinementStats refine_surface_to_size(Mesh& m, double size);

}  // namespace vd
