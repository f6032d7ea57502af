#include "geometry/predicates.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>

#include <algorithm>
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
  // The oriented in-sphere test times the orientation, as CGAL's
  // side_of_bounded_sphere_3 does, so a flat tetrahedron yields ON_BOUNDARY.
  // Both factors have static filters in Epick; the bounded-sphere functor
  // has only the interval filter, which was 37 % of a run on
  // gmsh_ellipses.brep (the sliver pass's facet witnesses).
  const Point pa = to_cgal(a), pb = to_cgal(b), pc = to_cgal(c), pd = to_cgal(d);
  const int o = static_cast<int>(CGAL::orientation(pa, pb, pc, pd));
  if (o == 0) return SphereSide::on_boundary;
  const int s = static_cast<int>(CGAL::side_of_oriented_sphere(pa, pb, pc, pd, to_cgal(p))) * o;
  return s > 0 ? SphereSide::inside : s < 0 ? SphereSide::outside : SphereSide::on_boundary;
}

SphereSide perturbed_side_of_circumsphere(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d,
                                          const Vec3& p, bool* cospherical) {
  const Point pa = to_cgal(a), pb = to_cgal(b), pc = to_cgal(c), pd = to_cgal(d), pp = to_cgal(p);
  const int s = static_cast<int>(CGAL::side_of_oriented_sphere(pa, pb, pc, pd, pp));
  if (cospherical) *cospherical = s == 0;
  if (s != 0) return s > 0 ? SphereSide::inside : SphereSide::outside;
  // On the sphere. The perturbed determinant's leading terms belong to the
  // points last in x, y, z order: the last two decide. When the last is p,
  // its own lift puts it outside; when it is a corner of the tetrahedron,
  // the sign is the orientation of the tetrahedron with p in that corner's
  // place (nonzero for one of the two: four of the five points are never
  // coplanar in both).
  const Point* order[5] = {&pa, &pb, &pc, &pd, &pp};
  std::sort(order, order + 5, [](const Point* x, const Point* y) { return CGAL::compare_xyz(*x, *y) == CGAL::SMALLER; });
  for (int i = 4; i > 2; --i) {
    const Point* q = order[i];
    if (q == &pp) return SphereSide::outside;
    int o = 0;
    if (q == &pd) o = static_cast<int>(CGAL::orientation(pa, pb, pc, pp));
    else if (q == &pc) o = static_cast<int>(CGAL::orientation(pa, pb, pp, pd));
    else if (q == &pb) o = static_cast<int>(CGAL::orientation(pa, pp, pc, pd));
    else o = static_cast<int>(CGAL::orientation(pp, pb, pc, pd));
    if (o != 0) return o > 0 ? SphereSide::inside : SphereSide::outside;
  }
  return SphereSide::outside;  // not reached for a positive tetrahedron
}

SphereSide side_of_equatorial_sphere(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& p) {
  if (collinear(a, b, c)) return SphereSide::on_boundary;
  return to_side(
      K().side_of_bounded_sphere_3_object()(to_cgal(a), to_cgal(b), to_cgal(c), to_cgal(p)));
}

namespace {
bool finite(const Vec3& x) { return std::isfinite(x.x) && std::isfinite(x.y) && std::isfinite(x.z); }
}  // namespace

Ball circumsphere(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
  if (orientation(a, b, c, d) == 0) return {a, kInfinity};
  const Point o = CGAL::circumcenter(to_cgal(a), to_cgal(b), to_cgal(c), to_cgal(d));
  const Vec3 centre{o.x(), o.y(), o.z()};
  // Nearly flat, the centre overflows in doubles; the distances below were
  // then NaN and the radius came out 0 (std::max drops a NaN).
  if (!finite(centre)) return {a, kInfinity};
  // The largest of the four distances bounds the construction error from above.
  double r = 0;
  for (const Vec3& v : {a, b, c, d}) r = std::max(r, norm(v - centre));
  return {centre, r};
}

Ball equatorial_sphere(const Vec3& a, const Vec3& b, const Vec3& c) {
  if (collinear(a, b, c)) return {a, kInfinity};
  const Point o = CGAL::circumcenter(to_cgal(a), to_cgal(b), to_cgal(c));
  const Vec3 centre{o.x(), o.y(), o.z()};
  if (!finite(centre)) return {a, kInfinity};
  double r = 0;
  for (const Vec3& v : {a, b, c}) r = std::max(r, norm(v - centre));
  return {centre, r};
}

double safe_radius(const Ball& ball) {
  const double coordinate_scale =
      std::max({std::abs(ball.centre.x), std::abs(ball.centre.y), std::abs(ball.centre.z)});
  return ball.radius * (1 + 1e-6) + 1e-12 * coordinate_scale;
}

}  // namespace vd
