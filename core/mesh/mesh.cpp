#include "mesh/mesh.h"

#include <cmath>
#include <cstdint>
#include <cstring>
#include <set>
#include <unordered_map>

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

std::vector<int> face_groups_of(const Mesh& m, int face) {
  const auto it = m.face_groups.find(face);
  return it != m.face_groups.end() ? it->second : std::vector<int>{face};
}

std::map<int, std::vector<int>> number_shared_pieces(std::vector<int>& ids, const std::vector<std::vector<int>>& groups,
                                                     int last_id) {
  std::map<int, std::set<std::vector<int>>> kinds;  // id -> the face lists of its pieces
  for (size_t i = 0; i < ids.size(); ++i)
    kinds[ids[i]].insert(groups[i].size() > 1 ? groups[i] : std::vector<int>{ids[i]});
  std::map<std::vector<int>, int> own;  // face list -> its id of its own
  std::map<int, std::vector<int>> shared;
  for (size_t i = 0; i < ids.size(); ++i) {
    if (groups[i].size() < 2) continue;
    if (kinds[ids[i]].size() > 1) {
      const auto [it, added] = own.emplace(groups[i], last_id + 1);
      if (added) ++last_id;
      ids[i] = it->second;
    }
    shared[ids[i]] = groups[i];
  }
  return shared;
}

namespace {

// A point's coordinates as bits, -0 as +0 (the same point).
struct PointBits {
  std::uint64_t x, y, z;
  bool operator==(const PointBits& o) const { return x == o.x && y == o.y && z == o.z; }
};
struct PointBitsHash {
  size_t operator()(const PointBits& k) const {
    std::uint64_t h = k.x * 0x9E3779B97F4A7C15ull;
    h ^= (k.y + 0x7F4A7C159E3779B9ull + (h << 6) + (h >> 2));
    h ^= (k.z + 0x94D049BB133111EBull + (h << 6) + (h >> 2));
    return static_cast<size_t>(h ^ (h >> 31));
  }
};
std::uint64_t bits(double d) {
  if (d == 0) d = 0;
  std::uint64_t b;
  std::memcpy(&b, &d, sizeof b);
  return b;
}

// Every point id an element holds (corners and mid-edge nodes), in place.
template <class Visit>
void for_each_point_reference(Mesh& m, const Visit& visit) {
  for (Triangle& t : m.triangles)
    for (int& v : t.v) visit(v);
  for (Tetrahedron& t : m.tets)
    for (int& v : t.v) visit(v);
  for (auto& mid : m.triangle_mid)
    for (int& v : mid) visit(v);
  for (auto& mid : m.tet_mid)
    for (int& v : mid) visit(v);
}

// Each point id v becomes to[v]. An id of a point that does not exist stays
// (validation names it).
void renumber_point_references(Mesh& m, const std::vector<int>& to) {
  for_each_point_reference(m, [&](int& v) {
    if (v >= 0 && static_cast<size_t>(v) < to.size()) v = to[static_cast<size_t>(v)];
  });
}

}  // namespace

int weld_coincident_points(Mesh& m) {
  std::unordered_map<PointBits, int, PointBitsHash> first;
  first.reserve(m.points.size());
  std::vector<int> to(m.points.size());
  int repeats = 0;
  for (size_t i = 0; i < m.points.size(); ++i) {
    const Vec3& p = m.points[i];
    to[i] = static_cast<int>(i);
    // Non-finite points stay as they are (validation refuses them).
    if (!(std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z))) continue;
    const auto [it, fresh] = first.emplace(PointBits{bits(p.x), bits(p.y), bits(p.z)}, static_cast<int>(i));
    to[i] = it->second;
    repeats += !fresh;
  }
  if (repeats > 0) renumber_point_references(m, to);
  return repeats;
}

std::vector<int> drop_unused_points(Mesh& m) {
  std::vector<int> id(m.points.size(), -1);
  for_each_point_reference(m, [&](int& v) {
    if (v >= 0 && static_cast<size_t>(v) < id.size()) id[static_cast<size_t>(v)] = 0;
  });
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
  renumber_point_references(m, id);
  return id;
}

std::vector<char> surface_vertex_flags(size_t points, const std::vector<Triangle>& triangles) {
  std::vector<char> on_surface(points, 0);
  for (const Triangle& t : triangles)
    for (int v : t.v) on_surface[static_cast<size_t>(v)] = 1;
  return on_surface;
}

}  // namespace vd
