// Topological faces for input that has none (STL, OFF): smooth patches split
// at sharp edges. An edge is sharp when the normals of its two facets differ
// by more than `sharp_angle_deg`; non-manifold and open edges always split.
#pragma once

#include "mesh/mesh.h"
#include "surface/edge_map.h"

namespace vd {

constexpr double kDefaultSharpAngleDeg = 40.0;

// Gives every facet without a face (kNoFace) its patch's number, after the
// largest face id given (1..P when none is; patch order: by lowest facet
// index). Patches stop at facets with a face: given ids stay (a surface with
// one side untagged lost every id given, 2026-11-30). Returns P.
// `edges`, when given, is the surface's edge map (built here otherwise).
int assign_face_patches(Mesh& surface, double sharp_angle_deg = kDefaultSharpAngleDeg,
                        const EdgeMap* edges = nullptr);

// Twice the area of facet t, along its normal (right-hand rule).
Vec3 facet_area_vector(const std::vector<Vec3>& points, const Triangle& t);
// Unit normal of facet t (right-hand rule); zero for a degenerate facet.
Vec3 facet_normal(const std::vector<Vec3>& points, const Triangle& t);
double facet_area(const std::vector<Vec3>& points, const Triangle& t);
// The angle (radians) at `apex` between the directions to p and q; atan2,
// which keeps its digits near 0 and pi where acos does not.
double corner_angle(const Vec3& apex, const Vec3& p, const Vec3& q);
// The smallest of facet t's three corner angles (radians).
double smallest_corner_angle(const std::vector<Vec3>& points, const Triangle& t);

}  // namespace vd
