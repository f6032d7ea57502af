// Random shift of vertex positions (paper §3): moves every vertex by a small
// seeded random vector so that no five vertices are co-spherical. Surface
// vertices move only in their tangent plane, vertices on a feature edge only
// along it, corners not at all, so the surface keeps its shape.
#pragma once

#include <cstdint>
#include <vector>

#include "mesh/mesh.h"
#include "surface/edge_map.h"

namespace vd {

struct ShiftOptions {
  double relative = 1e-4;  // of the local edge length
  std::uint64_t seed = 1;
  // An edge where the facet normals turn by more than this is a feature edge
  // even inside one topological face (an OBJ group may wrap a box's corner),
  // as for face patches (--sharp-angle).
  double crease_angle_deg = 40.0;
};

struct ShiftStats {
  int moved_free = 0;       // volume vertices
  int moved_in_plane = 0;   // smooth surface vertices
  int moved_on_edge = 0;    // feature-edge vertices
  int fixed = 0;            // corners, and moves refused because a facet would turn over
  int restored = 0;         // surface vertices put back after the volume (restore_surface_positions)
};

// Shifts m.points in place. Vertices of m.triangles are surface vertices;
// the others (interior vertices) move freely.
// `edges`, when given, is the edge map of m.triangles (built here otherwise).
ShiftStats random_shift(Mesh& m, const ShiftOptions& options, const EdgeMap* edges = nullptr);

// Puts surface vertices back where they were before the shift (`before`,
// indexed as m.points) where they have not moved since (still at
// `shifted`) and every tetrahedron around them stays positive (exact
// orientation) with its smallest dihedral angle at least the smaller of
// its own and `keep_above_deg` (the sliver pass's angle: what it reached
// is kept). The tangent plane of the shift is the facets', not the
// true surface's: on CAD input it took nodes of a radius-3 cylinder up to
// 1.1e-6 off it, past the tolerance FreeCAD's constraints find their nodes
// by (a pressure on a hole loaded 2.2 % of its area). Returns the number of
// vertices put back.
int restore_surface_positions(Mesh& m, const std::vector<Vec3>& before, const std::vector<Vec3>& shifted,
                              double keep_above_deg);

}  // namespace vd
