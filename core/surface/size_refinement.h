// Surface edges brought down to the requested size before Delaunayzation.
// Delaunayzation splits only what is not Delaunay: a 10 x 1 box given as 12
// triangles stays 12 triangles, and with `--size 0.5` the interior vertices
// then meet facets fifty times their size, which makes tetrahedra no solver
// can use. So with a size given (--size, or sizes per input vertex), every
// surface edge longer than kLongestEdgeOverSize times the size there is split
// at its mid-point, longest first, in every facet that shares it. The mid-point lies on the input
// facets, so the surface keeps its exact shape (CAD input is refined on the
// CAD geometry instead, in core/cad).
//
// With interior vertices the surface's own graded size bounds the edges too
// (--surface-grading): a needle or a cap on the input makes every tetrahedron
// on it flat, whatever the interior vertices do. Its long edges are split
// until the edges near its short edge are about that short, growing away
// from it by the gradation, with flips inside faces towards the Delaunay
// criterion before each pass: splits alone cut a needle into more needles.
// The graded sizes may also bound edges through space (GradedSizes::in_space):
// a fine surface near big facets of a part it shares no edge with.
#pragma once

#include <functional>
#include <vector>

#include "mesh/mesh.h"

namespace vd {

// The longest edge kept at size h is sqrt(2) h. Splits halve edges, so they
// end between h / sqrt(2) and sqrt(2) h, around h in ratio, as unit-length
// remeshers keep them, and as long as the interior lattice's (spaced h).
// With h itself as the bound they ended between h / 2 and h: the unit box at
// 0.0425 got edges of 0.52 h and 0.74 h, and the offsets of its facets came
// twice as dense as the lattice behind them (4,888 slivers before the pass
// at 169k tetrahedra; 1,878 at 125k now).
constexpr double kLongestEdgeOverSize = 1.4142135623730951;

struct SizeRefinementStats {
  int splits = 0;      // edges split
  int passes = 0;
  int flips = 0;
};

// `size` > 0: the target edge length everywhere (edges longer than
// kLongestEdgeOverSize times it are split); per-vertex sizes in
// m.point_size (when given, > 0) lower it locally (mean of the two ends).
// Nothing to do when neither is given.
// `graded` (one per point of m, or empty): sizes that also bound the edges
// (an edge is split when longer than `graded_factor` times the mean of its
// ends'); a mid-point gets the smaller of its ends' sizes grown by
// `gradation` times its distance to them.
struct GradedSizes {
  std::vector<double> size;
  double gradation = 0.3;
  double factor = 2.0;
  double flip_ridge_deg = 0;  // > 0: flips inside faces before each pass
  // When set, sizes in space (a SizeField from `size`): an edge is also split
  // when longer than `factor` times the size at its mid-point, and a new
  // vertex's size is at most the size there.
  std::function<double(const Vec3&)> in_space;
  // Vertices (of the input) where a face's own angle is sharp: edges at
  // them are not graded. A spike or a needle face is thin by design, and
  // splitting its edges fills it with vertices no tetrahedron can join
  // fairly (plc-sharp's spike: 20.1 -> 0.07 deg).
  std::vector<char> sharp_corner;
  bool at_sharp_corner(int v) const { return v < static_cast<int>(sharp_corner.size()) && sharp_corner[v]; }
};
SizeRefinementStats refine_surface_to_size(Mesh& m, double size, GradedSizes* graded = nullptr);

// The surface's own size at each vertex: its shortest edge, limited by its
// neighbours' sizes grown by `gradation` times the distance along the edges
// (Dijkstra over the edge graph), so that a short edge asks for small edges
// around it and the sizes grow smoothly away from it.
std::vector<double> graded_edge_sizes(const Mesh& m, double gradation);

// Per point of m: is it a corner where some face's angle (the sum of its
// facets' corners there) is under limit_deg?
std::vector<char> sharp_face_corners(const Mesh& m, double limit_deg);

}  // namespace vd
