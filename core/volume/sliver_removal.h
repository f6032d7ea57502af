// Sliver removal (paper §7) on the tetrahedra of a finished mesh.
//
// Case A: a sliver with two faces on the surface (the flat tetrahedra that
// four nearly coplanar surface vertices make) is removed, and its other two
// faces replace those two facets, under the rules of a surface flip: same
// topological face, same regions, ridge angle under the limit (on CAD input
// also, as a flip of Delaunayzation may, across a ridge under the flip angle
// when the surface moves by at most the face's chord height). Only slivers
// against the exterior are removed; an interface sliver would have to change
// region instead.
// Case B (volume/sliver_improvement.h): an interior sliver is removed by a
// 2-3 flip across one of its faces or by removing one of its edges (3-2 flip
// and its generalisation), inside one region, when the smallest dihedral
// angle of the tetrahedra involved grows.
// Case C (same file): the sliver is opened by moving one of its vertices to
// where the smallest dihedral angle around that vertex is largest: an
// interior vertex anywhere, a surface vertex within the plane of its flat
// patch or along its straight crease, and on CAD input one inside a curved
// face on that face. B and C never flip a surface facet, and change the
// surface's shape only there, so the surface and its tags stay as case A
// left them.
#pragma once

#include <array>
#include <functional>
#include <vector>

#include "mesh/mesh.h"
#include "quality/tet_quality.h"

namespace vd {

class SurfaceGeometry;

// The largest sliver angle an option may ask: every tetrahedron has a
// dihedral angle of at most 70.53 deg (the regular one's, all six), so above
// that every tetrahedron would be a sliver. --sliver-angle 90 took
// gmsh_part.step's pass from 0.04 to 41 s, and left its mesh no better.
constexpr double kLargestSliverAngleDeg = 70.5;

struct SliverOptions {
  double sliver_angle_deg = 20.0;  // tetrahedra with a smaller dihedral angle are slivers
  // When cases B and C leave no tetrahedron under the sliver angle, they go
  // on with this one (0 or not larger: they stop). Aiming higher costs
  // little where the first aim was reached, and much where slivers stay.
  double raised_angle_deg = 0;
  // At the raised angle the passes stop after max(raised_changes_per_first
  // times the changes made at the first angle, raised_changes_at_least):
  // every change keeps its tetrahedra above those it replaces, so they may
  // stop anywhere (sliver_improvement.cpp).
  long raised_changes_per_first = 4;
  long raised_changes_at_least = 10000;
  // Case A: largest angle between the two new facets. Small, because on a
  // curved face the new facets leave the input surface by about this angle
  // times their size, and B and C clear most slivers without it.
  double ridge_angle_deg = 0.1;
  // CAD input: case A also replaces a pair that a flip of Delaunayzation
  // could, across a ridge of up to flip_ridge_deg, when the surface moves by
  // at most the face's chord height (the distance between the two
  // diagonals): by face id where > 0, else chord_height; 0: no such case.
  std::vector<double> face_chord_height;
  double chord_height = 0;
  double flip_ridge_deg = 20.0;
  bool flips = true;               // case B
  bool moves = true;               // case C
  // Case D: a new interior vertex where flips and moves left a sliver;
  // not with delaunay_surface (it could take a facet's empty sphere).
  bool inserts = true;
  // CAD input: case C also moves a vertex inside a curved face on that face
  // (SurfaceGeometry::project_onto_face). Null: surface vertices slide only in planes.
  const SurfaceGeometry* geometry = nullptr;
  // Case C, once the passes stop: more passes in which the tetrahedra
  // around a moved vertex that are worse than the sliver mended are held
  // (may not get worse) instead of scoring the move (sliver_improvement.cpp).
  bool hold_worse = true;
  // Case C keeps every surface facet a face of the Delaunay
  // tetrahedralization of the vertices (FacetWitnesses): a move that would
  // put a vertex into every empty sphere of a facet is refused. Off by
  // default since 2026-12-02: the mesh stays valid and conforming without
  // it (moves change no tetrahedron's vertices, only their shape, and are
  // taken only when every tetrahedron around the vertex stays positive),
  // the paper asks nothing more of case C, and those refusals were what
  // held the worst tetrahedra: caxif_as1-oc-214.stp 9.16 -> 17.23 deg,
  // cgal_anchor_dense.off 6.02 -> 14.72, occt_MODERN_Exhaust_1.brep 0.15 ->
  // 2.41, gmsh_simple_plane.brep 1.42 -> 4.55 (README, "Quality and
  // slivers"). On (`--delaunay-surface`, and always without interior
  // vertices, mesher.cpp): the surface stays a conforming Delaunay one, as
  // recovery left it, for a caller who tetrahedralizes the output's
  // vertices again.
  bool delaunay_surface = false;
  // With more than one thread, the facet witnesses are built on a second
  // one beside the complex. A second thread allocates in an arena of its
  // own, in fresh pages: where the complex reuses the heap the freed
  // tetrahedralization left, the witnesses' page faults cost more than the
  // thread saves (the 125k box's pass on two threads: 0.068 s with them
  // built on the first thread, 0.088 s beside; medians of 12 runs).
  bool witnesses_beside = true;
  int max_passes = 8;              // of cases B and C over the remaining slivers
};

// The capacity the sliver pass's arrays of n tetrahedra start with: room for
// those its flips add (a few per cent at most) without doubling any of them.
inline size_t sliver_pass_room(size_t n) { return n + n / 8 + 1024; }

struct SliverStats {
  double angle_deg = 0;         // the sliver angle used
  double raised_to_deg = 0;     // the raised angle, when the pass went on to it; else 0
  bool delaunay_surface = false;  // SliverOptions::delaunay_surface: moves kept the facets Delaunay
  long raised_changes = 0;      // flips and moves made at the raised angle
  bool raised_allowance_used = false;  // the raised angle's passes stopped at their allowance
  long slivers_before = 0;      // tetrahedra under the sliver angle
  long removed_boundary = 0;    // case A
  long removed_across_ridges = 0;  // of which over the ridge angle, within the chord height (CAD input)
  long removed_crease_caps = 0;    // of which across a face border, over a facet that is a crease
  long flips_23 = 0;            // case B: face swaps (two tetrahedra into three)
  long flips_32 = 0;            // case B: edge with three tetrahedra around it (three into two)
  long edge_removals = 0;       // case B: edge with four to seven tetrahedra around it
  long insertions = 0;          // case D: new interior vertices
  long moves = 0;               // case C: vertices moved
  long surface_moves = 0;       // of which surface vertices, in their flat patch or along their crease
  long moves_blocked = 0;       // case C: better position found, refused to keep a surface facet
                                // Delaunay (delaunay_surface only)
  long held_moves = 0;          // of the moves, those made holding worse tetrahedra (hold_worse)
  long slivers_after = 0;
  // Over all tetrahedra, before case A and after the last pass.
  double min_dihedral_before_deg = 0, min_dihedral_after_deg = 0;
  long below_5_before = 0, below_10_before = 0, below_5_after = 0, below_10_after = 0;
};

// Case A alone (counts into stats.removed_boundary).
void remove_boundary_slivers(Mesh& m, const SliverOptions& options, SliverStats& stats);

// For each triangle, the vertices opposite it in the two tetrahedra beside it
// in the Delaunay tetrahedralization of the mesh's points (in either order),
// -1 for a convex-hull side, {-2, -2} when it is not a face
// (DelaunayTetrahedralization::facet_apexes).
using FacetApexes = std::function<std::vector<std::array<int, 2>>(const std::vector<Triangle>& triangles)>;

// Cases A, B and C in that order, with the before / after figures; the
// quality summary of the result into *after when given (the same as
// summarize_quality's, without measuring every tetrahedron again).
// `apexes_done` (may be empty) is called once `apexes` is no longer needed:
// the pipeline frees its tetrahedralization there, before the passes that
// hold a second copy of the tetrahedra (a third of the peak memory).
// Pre: every surface facet is a face of the Delaunay tetrahedralization
// that `apexes` describes (case A keeps it so: its new facets are faces of
// the Delaunay tetrahedra it removes).
SliverStats remove_slivers(Mesh& m, const SliverOptions& options, const FacetApexes& apexes,
                           QualitySummary* after = nullptr, const std::function<void()>& apexes_done = {});

}  // namespace vd
