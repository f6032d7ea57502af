// Exact geometric predicates on vdmesh points (CGAL's filtered exact
// predicates behind a CGAL-free header). Every Delaunayhood decision of the
// facet oracles ends in one of these, so that floating-point noise can make an
// oracle slow or conservative, never wrong.
//
// Convention for the "empty sphere" tests: a point ON a sphere counts as
// inside (SphereSide::on_boundary is not "outside"). A sphere with a fourth
// point on it does not prove anything in a degenerate configuration, so
// treating it as occupied keeps every "Delaunay" answer a strong one.
#pragma once

#include "mesh/mesh.h"

namespace vd {

enum class SphereSide { inside, on_boundary, outside };

// Sign of det(b - a, c - a, d - a): +1 for a positive tetrahedron (mesh.h),
// -1 for a negative one, 0 when the four points are coplanar.
int orientation(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d);

// Sign of the turn a -> b -> c in a plane (a face's (u, v)): +1 counter-
// clockwise, -1 clockwise, 0 collinear. Exact, as the 3D one.
int orientation_2d(double ax, double ay, double bx, double by, double cx, double cy);

// True when a, b, c lie on one line (or coincide).
bool collinear(const Vec3& a, const Vec3& b, const Vec3& c);

// Side of p with respect to the circumsphere of tetrahedron (a, b, c, d),
// either orientation. Pre: orientation(a, b, c, d) != 0 (otherwise the answer
// is on_boundary, which the empty tests read as "occupied").
SphereSide side_of_circumsphere(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d,
                                const Vec3& p);

// The same for a positively oriented tetrahedron, never on_boundary: five
// cospherical points are told apart by the symbolic perturbation that CGAL's
// Delaunay tetrahedralization uses (Devillers and Teillaud: each point lifted
// by a power of epsilon, the higher the later it comes in x, y, z order), so
// that every vertex set has one Delaunay tetrahedralization, the same as
// CGAL's. Pre: orientation(a, b, c, d) > 0 and p is none of them.
// *cospherical, when given, tells whether the perturbation decided.
SphereSide perturbed_side_of_circumsphere(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d,
                                          const Vec3& p, bool* cospherical = nullptr);
// Side of p with respect to the equatorial (smallest, diametral) sphere of
// triangle (a, b, c). A collinear triangle answers on_boundary.
SphereSide side_of_equatorial_sphere(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& p);

// "Occupied" in the sense of the convention above: inside or on the sphere.
inline bool occupies(SphereSide s) { return s != SphereSide::outside; }

// Approximate constructions (doubles) used to choose candidates before the
// exact tests; callers add a safety margin to the radius.
struct Ball {
  Vec3 centre;
  double radius = 0;
};
// Circumsphere of a non-degenerate tetrahedron; radius +inf when flat.
Ball circumsphere(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d);
// Equatorial sphere of a triangle; radius +inf when collinear.
Ball equatorial_sphere(const Vec3& a, const Vec3& b, const Vec3& c);
// The radius to search around ball.centre so that no vertex the exact test
// would call inside or on the sphere is left out by rounding of the centre.
double safe_radius(const Ball& ball);

}  // namespace vd
