// Closed, tagged test and demo surfaces built by vdmesh itself: the paper's
// cases (sphere, pyramids, needle box) and simple solids. Each shape is one
// region; faces are numbered from `first_face`.
#pragma once

#include "mesh/mesh.h"

namespace vd::shapes {

// Axis-aligned box [lo, hi], each side split into n x n squares (2 triangles
// each); 6 faces, normals out of region `region`.
Mesh box(Vec3 lo, Vec3 hi, int n = 1, int region = 1, int first_face = 1);
// Icosahedron refined `levels` times, projected on the sphere; one face.
Mesh icosphere(Vec3 centre, double radius, int levels, int region = 1, int first_face = 1);
// Square pyramid: base centre, base side, height (negative: pointing down);
// 5 faces: the base (2 triangles) and the 4 sides.
Mesh pyramid(Vec3 base_centre, double side, double height, int region = 1, int first_face = 1);
// Box with a square through-hole along z: a genus-1 solid, planar faces whose
// triangles are long needles (paper §9.1 style).
Mesh box_with_hole(Vec3 lo, Vec3 hi, double hole_fraction, int region = 1, int first_face = 1);

// Appends b to a (vertex ids shifted). Shapes that touch are not merged.
void append(Mesh& a, const Mesh& b);
// Merges vertices with identical coordinates (exact), dropping unused ones.
void weld_exact(Mesh& m);
// Where two solids touch, their coincident facets (same vertices, opposite
// orientation) become one interface facet: the first one is kept and its
// front region set to the other's back region. Call after weld_exact.
void merge_coincident_facets(Mesh& m);

}  // namespace vd::shapes
