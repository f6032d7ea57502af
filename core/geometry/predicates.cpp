#include "geometry/predicates.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>

#include <cmath>
#include <limits>

namespace vd {
namespace {
using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = K::Point_3;

Point to_cgal(const Vec3& p) { return {p.x, p.y, p.z}; }

SphereSide to_side(CGAL::Bounded_side s) {
  if (s == CGAL::ON_BOUNDED_SIDE) return SphereSide::inside;
  if (s == CGAL::ON_BOUNDARY) return SphereSide::on_boundary;
  return SphereSide::outside;
}

constexpr double kInfinity = std::numeric_limits<double>::infinity();
}  // namespace

int orientation(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
  return static_cast<int>(CGAL::orientation(to_cgal(a), to_cgal(b), to_cgal(c), to_cgal(d)));
}

int orientation_2d(double ax, double ay, double bx, double by, double cx, double cy) {
  return static_cast<int>(CGAL::orientation(K::Point_2(ax, ay), K::Point_2(bx, by), K::Point_2(cx, cy)));
}

bool collinear(const Vec3& a, const Vec3& b, const Vec3& c) {
  return CGAL::collinear(to_cgal(a), to_cgal(b), to_cgal(c));
}

SphereSide side_of_circumsphere(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d,
                                const Vec3& p) {
  // CGAL multiplies by the orientation, so a flat tetrahedron yields
  // ON_BOUNDARY rather than tripping a precondition.
  return to_side(K().side_of_bounded_sphere_3_object()(to_cgal(a), to_cgal(b), to_cgal(c),
                                                        to_cgal(d), to_cgal(p)));
}

SphereSide side_of_equatorial_sphere(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& p) {
  if (collinear(a, b, c)) return SphereSide::on_boundary;
  return to_side(
      K().side_of_bounded_sphere_3_object()(to_cgal(a), to_cgal(b), to_cgal(c), to_cgal(p)));
}

Ball circumsphere(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
  if (orientation(a, b, c, d) == 0) return {a, kInfinity};
  const Point o = CGAL::circumcenter(to_cgal(a), to_cgal(b), to_cgal(c), to_cgal(d));
  const Vec3 centre{o.x(), o.y(), o.z()};
  // The largest of the four distances bounds the construction error from above.
  double r = 0;
  for (const Vec3& v : {a, b, c, d}) r = std::max(r, norm(v - centre));
  return {centre, r};
}

Ball equatorial_sphere(const Vec3& a, const Vec3& b, const Vec3& c) {
  if (collinear(a, b, c)) return {a, kInfinity};
  const Point o = CGAL::circumcenter(to_cgal(a), to_cgal(b), to_cgal(c));
  const Vec3 centre{o.x(), o.y(), o.z()};
  double r = 0;
  for (const Vec3& v : {a, b, c}) r = std::max(r, norm(v - centre));
  return {centre, r};
}

}  // namespace vd
