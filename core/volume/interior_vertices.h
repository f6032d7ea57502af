// Interior vertices (paper §2): first vertices offset inward from the facet
// barycentres (on both sides of an interface), then an octree whose leaves
// follow the size field, with points at leaf centres and edge mid-points so
// that a uniform size gives a face-centred cubic lattice (of spacing H under
// --size H; stretched by 3 % along two axes, so that its Delaunay
// tetrahedralization has no cospherical vertices to split into slivers).
// A candidate is dropped when it is too close to another vertex or to the
// surface, or (unlike the paper) when it is not inside a region, so that
// exterior points cannot spoil the surface's Delaunayhood. About 1% jitter.
#pragma once

#include <atomic>
#include <cstdint>
#include <functional>
#include <vector>

#include "mesh/mesh.h"
#include "volume/size_field.h"

namespace vd {

struct InteriorOptions {
  double offset = 0.8;            // stage 1: offset x facet size (apex height of a regular tet: 0.816)
  double min_vertex_gap = 0.65;   // x h: nearer to another vertex is dropped
  double min_surface_gap = 0.45;  // x h: nearer to a facet is dropped
  double jitter = 0.01;           // x h
  std::uint64_t seed = 1;
  int max_octree_depth = 14;
  const std::atomic<bool>* cancel = nullptr;  // looked at every few hundred candidates
  // When set, a candidate for which it answers true is dropped too (the
  // pipeline's: the point would take a surface facet out of the Delaunay
  // tetrahedralization). Asked last, of the candidates every other test kept.
  std::function<bool(const Vec3&)> takes_a_facet;
};

struct InteriorStats {
  long offset_points = 0, lattice_points = 0;
  long candidates = 0, rejected_outside = 0, rejected_near_vertex = 0, rejected_near_surface = 0;
  long rejected_taking_a_facet = 0;  // InteriorOptions::takes_a_facet
  // A recovery after the first stopped, and the run was made again
  // cautiously: candidates that take no surface facet, no cap fold splits
  // (pipeline/mesher.cpp).
  bool cautious_retry = false;
  long cap_points = 0;  // added after the tetrahedra, to open flat caps (volume/cap_vertices.h)
  long cap_points_refused = 0;  // not added: a surface facet would have stopped being Delaunay
  long cap_points_fallback = 0;  // of cap_points, put under another edge of the cap than its fold
  long cap_folds_split = 0;     // fold edges of refused caps split on the surface (volume/cap_vertices.h)
  long cap_folds_at_sharp_corners = 0;  // of those folds, the sides of sharp face corners, left unsplit
  bool cap_fold_round_undone = false;  // the last round's recovery stopped; the mesh is the one before it
};

// `region_at(p)` gives the region containing p (0 outside). Returns the new
// points (not yet in m); `regions`, when given, receives the region of each.
std::vector<Vec3> generate_interior_vertices(const Mesh& m, const SizeField& size,
                                             const std::function<int(const Vec3&)>& region_at,
                                             const InteriorOptions& options, InteriorStats& stats,
                                             std::vector<int>* regions = nullptr);

// Distance from p to triangle (a, b, c).
double point_triangle_distance(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c);

}  // namespace vd
