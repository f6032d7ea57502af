#include "geometry/triangle_index.h"

#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/Simple_cartesian.h>

#include <algorithm>
#include <cmath>
#include <iterator>

namespace vd {
namespace {

using K = CGAL::Simple_cartesian<double>;
using Point = K::Point_3;
using Triangle3 = K::Triangle_3;
using Iterator = std::vector<Triangle3>::const_iterator;
using Primitive = CGAL::AABB_triangle_primitive<K, Iterator>;
using Tree = CGAL::AABB_tree<CGAL::AABB_traits<K, Primitive>>;

Point point(const Vec3& p) { return Point(p.x, p.y, p.z); }

}  // namespace

struct TriangleIndex::Impl {
  std::vector<Triangle3> triangles;
  std::vector<int> ids;  // position in `triangles` -> id given by the caller
  Tree tree;
};

TriangleIndex::TriangleIndex(const std::vector<std::array<Vec3, 3>>& triangles) : impl_(new Impl) {
  impl_->triangles.reserve(triangles.size());
  for (size_t i = 0; i < triangles.size(); ++i) {
    const auto& t = triangles[i];
    if (norm(cross(t[1] - t[0], t[2] - t[0])) == 0) continue;
    impl_->triangles.emplace_back(point(t[0]), point(t[1]), point(t[2]));
    impl_->ids.push_back(static_cast<int>(i));
  }
  if (impl_->triangles.empty()) return;
  impl_->tree.insert(impl_->triangles.cbegin(), impl_->triangles.cend());
  impl_->tree.build();
  impl_->tree.accelerate_distance_queries();
}

TriangleIndex::~TriangleIndex() = default;

bool TriangleIndex::empty() const { return impl_->triangles.empty(); }

TriangleIndex::Hit TriangleIndex::closest(const Vec3& p) const {
  Hit h;
  if (empty()) return h;
  const Point q = point(p);
  const auto pp = impl_->tree.closest_point_and_primitive(q);
  h.id = impl_->ids[static_cast<size_t>(pp.second - impl_->triangles.cbegin())];
  h.distance = std::sqrt(CGAL::squared_distance(q, pp.first));
  h.point = Vec3{pp.first.x(), pp.first.y(), pp.first.z()};
  return h;
}

void TriangleIndex::within(const Vec3& p, double d, std::vector<int>& out) const {
  out.clear();
  if (empty()) return;
  const K::Iso_cuboid_3 box(p.x - d, p.y - d, p.z - d, p.x + d, p.y + d, p.z + d);
  std::vector<Iterator> hits;
  impl_->tree.all_intersected_primitives(box, std::back_inserter(hits));
  const Point q = point(p);
  for (const Iterator& it : hits)
    if (CGAL::squared_distance(q, *it) <= d * d) out.push_back(impl_->ids[static_cast<size_t>(it - impl_->triangles.cbegin())]);
}

double TriangleIndex::distance(int id, const Vec3& p) const {
  // Ids are kept in increasing order, so the position is found by search.
  const auto it = std::lower_bound(impl_->ids.begin(), impl_->ids.end(), id);
  if (it == impl_->ids.end() || *it != id) return std::numeric_limits<double>::infinity();
  return std::sqrt(CGAL::squared_distance(point(p), impl_->triangles[static_cast<size_t>(it - impl_->ids.begin())]));
}

}  // namespace vd
