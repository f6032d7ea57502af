#include "pipeline/input_facets.h"

#include <algorithm>

#include "geometry/triangle_index.h"

namespace vd {

std::vector<int> input_facets_under(const Mesh& input, const Mesh& changed, const std::vector<int>& facets) {
  std::vector<std::array<Vec3, 3>> triangles;
  triangles.reserve(input.triangles.size());
  for (const Triangle& t : input.triangles)
    triangles.push_back({input.points[t.v[0]], input.points[t.v[1]], input.points[t.v[2]]});
  const TriangleIndex index(triangles);
  std::vector<int> out;
  for (const int f : facets) {
    const Vec3 &a = changed.points[changed.triangles[f].v[0]], &b = changed.points[changed.triangles[f].v[1]],
               &c = changed.points[changed.triangles[f].v[2]];
    // The centroid and a point towards each corner: a facet flipped across
    // two input facets lies on both.
    for (const Vec3& p : {(1.0 / 3) * (a + b + c), 0.25 * (2.0 * a + b + c), 0.25 * (a + 2.0 * b + c),
                          0.25 * (a + b + 2.0 * c)})
      if (const int id = index.closest(p).id; id >= 0) out.push_back(id);
  }
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}

}  // namespace vd
