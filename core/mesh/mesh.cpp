#include "mesh/mesh.h"

#include <cmath>

namespace vd {

bool Mesh::has_region_tags() const {
  for (const Triangle& t : triangles)
    if (t.front == kUnknownRegion || t.back == kUnknownRegion) return false;
  return !triangles.empty();
}

bool Mesh::has_face_tags() const {
  for (const Triangle& t : triangles)
    if (t.face == kNoFace) return false;
  return !triangles.empty();
}

std::vector<int> drop_unused_points(Mesh& m) {
  std::vector<int> id(m.points.size(), -1);
  for (const Triangle& t : m.triangles)
    for (int v : t.v) id[v] = 0;
  for (const Tetrahedron& t : m.tets)
    for (int v : t.v) id[v] = 0;
  for (const auto& mid : m.triangle_mid)
    for (int v : mid) id[v] = 0;
  for (const auto& mid : m.tet_mid)
    for (int v : mid) id[v] = 0;
  int next = 0;
  for (size_t v = 0; v < m.points.size(); ++v) {
    if (id[v] < 0) continue;
    id[v] = next;
    m.points[next] = m.points[v];
    if (!m.point_size.empty()) m.point_size[next] = m.point_size[v];
    ++next;
  }
  if (next == static_cast<int>(m.points.size())) return {};
  m.points.resize(next);
  if (!m.point_size.empty()) m.point_size.resize(next);
  for (Triangle& t : m.triangles)
    for (int& v : t.v) v = id[v];
  for (Tetrahedron& t : m.tets)
    for (int& v : t.v) v = id[v];
  for (auto& mid : m.triangle_mid)
    for (int& v : mid) v = id[v];
  for (auto& mid : m.tet_mid)
    for (int& v : mid) v = id[v];
  return id;
}

std::vector<char> surface_vertex_flags(size_t points, const std::vector<Triangle>& triangles) {
  std::vector<char> on_surface(points, 0);
  for (const Triangle& t : triangles)
    for (int v : t.v) on_surface[static_cast<size_t>(v)] = 1;
  return on_surface;
}

}  // namespace vd
