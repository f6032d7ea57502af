#include "pipeline/input_facets.h"

#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/Simple_cartesian.h>

#include <algorithm>

namespace vd {

std::vector<int> input_facets_under(const Mesh& input, const Mesh& changed, const std::vector<int>& facets) {
  using K = CGAL::Simple_cartesian<double>;
  using Triangle3 = K::Triangle_3;
  using Primitive = CGAL::AABB_triangle_primitive<K, std::vector<Triangle3>::const_iterator>;
  using Tree = CGAL::AABB_tree<CGAL::AABB_traits<K, Primitive>>;
  const auto point = [](const Vec3& p) { return K::Point_3(p.x, p.y, p.z); };
  // Degenerate input facets are refused before anything changes the surface.
  std::vector<Triangle3> triangles;
  triangles.reserve(input.triangles.size());
  for (const Triangle& t : input.triangles)
    triangles.emplace_back(point(input.points[t.v[0]]), point(input.points[t.v[1]]), point(input.points[t.v[2]]));
  std::vector<int> out;
  if (triangles.empty()) return out;
  Tree tree(triangles.cbegin(), triangles.cend());
  tree.accelerate_distance_queries();
  for (const int f : facets) {
    const Vec3 &a = changed.points[changed.triangles[f].v[0]], &b = changed.points[changed.triangles[f].v[1]],
               &c = changed.points[changed.triangles[f].v[2]];
    // The centroid and a point towards each corner: a facet flipped across
    // two input facets lies on both.
    for (const Vec3& p : {(1.0 / 3) * (a + b + c), 0.25 * (2.0 * a + b + c), 0.25 * (a + 2.0 * b + c),
                          0.25 * (a + b + 2.0 * c)})
      out.push_back(static_cast<int>(tree.closest_point_and_primitive(point(p)).second - triangles.cbegin()));
  }
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}

}  // namespace vd
