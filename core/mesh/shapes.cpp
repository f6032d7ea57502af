#include "mesh/shapes.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <tuple>

namespace vd::shapes {
namespace {

int add_point(Mesh& m, Vec3 p) {
  m.points.push_back(p);
  return static_cast<int>(m.points.size()) - 1;
}

void add_tri(Mesh& m, int a, int b, int c, int face, int region) {
  m.triangles.push_back({{a, b, c}, face, 0, region});
}

// A planar quad grid from corner o along u and v (n x n cells); normal u x v.
void grid(Mesh& m, Vec3 o, Vec3 u, Vec3 v, int n, int face, int region) {
  std::vector<int> id((n + 1) * (n + 1));
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i)
      id[j * (n + 1) + i] = add_point(m, o + (double(i) / n) * u + (double(j) / n) * v);
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const int a = id[j * (n + 1) + i], b = id[j * (n + 1) + i + 1];
      const int c = id[(j + 1) * (n + 1) + i + 1], d = id[(j + 1) * (n + 1) + i];
      add_tri(m, a, b, c, face, region);
      add_tri(m, a, c, d, face, region);
    }
}

}  // namespace

Mesh box(Vec3 lo, Vec3 hi, int n, int region, int first_face) {
  Mesh m;
  const Vec3 dx{hi.x - lo.x, 0, 0}, dy{0, hi.y - lo.y, 0}, dz{0, 0, hi.z - lo.z};
  grid(m, lo, dy, dx, n, first_face + 0, region);       // z = lo, normal -z
  grid(m, lo + dz, dx, dy, n, first_face + 1, region);  // z = hi, normal +z
  grid(m, lo, dx, dz, n, first_face + 2, region);       // y = lo, normal -y
  grid(m, lo + dy, dz, dx, n, first_face + 3, region);  // y = hi, normal +y
  grid(m, lo, dz, dy, n, first_face + 4, region);       // x = lo, normal -x
  grid(m, lo + dx, dy, dz, n, first_face + 5, region);  // x = hi, normal +x
  weld_exact(m);
  return m;
}

Mesh icosphere(Vec3 centre, double radius, int levels, int region, int first_face) {
  Mesh m;
  const double t = (1.0 + std::sqrt(5.0)) / 2.0;
  const double base[12][3] = {{-1, t, 0}, {1, t, 0}, {-1, -t, 0}, {1, -t, 0}, {0, -1, t}, {0, 1, t},
                              {0, -1, -t}, {0, 1, -t}, {t, 0, -1}, {t, 0, 1}, {-t, 0, -1}, {-t, 0, 1}};
  for (auto& p : base) m.points.push_back(normalized({p[0], p[1], p[2]}));
  const int faces[20][3] = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11},
                            {1, 5, 9},  {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
                            {3, 9, 4},  {3, 4, 2},  {3, 2, 6},   {3, 6, 8},  {3, 8, 9},
                            {4, 9, 5},  {2, 4, 11}, {6, 2, 10},  {8, 6, 7},  {9, 8, 1}};
  for (auto& f : faces) add_tri(m, f[0], f[1], f[2], first_face, region);
  for (int level = 0; level < levels; ++level) {
    std::map<std::pair<int, int>, int> mid;
    auto midpoint = [&](int a, int b) {
      const auto key = std::minmax(a, b);
      auto it = mid.find(key);
      if (it != mid.end()) return it->second;
      const int id = add_point(m, normalized(0.5 * (m.points[a] + m.points[b])));
      mid.emplace(key, id);
      return id;
    };
    std::vector<Triangle> next;
    for (const Triangle& f : m.triangles) {
      const int a = f.v[0], b = f.v[1], c = f.v[2];
      const int ab = midpoint(a, b), bc = midpoint(b, c), ca = midpoint(c, a);
      for (auto tri : {std::array<int, 3>{a, ab, ca}, {b, bc, ab}, {c, ca, bc}, {ab, bc, ca}})
        next.push_back({tri, f.face, f.front, f.back});
    }
    m.triangles = std::move(next);
  }
  for (Vec3& p : m.points) p = centre + radius * p;
  return m;
}

Mesh pyramid(Vec3 c, double side, double height, int region, int first_face) {
  Mesh m;
  const double h = side / 2;
  const int p0 = add_point(m, c + Vec3{-h, -h, 0}), p1 = add_point(m, c + Vec3{h, -h, 0});
  const int p2 = add_point(m, c + Vec3{h, h, 0}), p3 = add_point(m, c + Vec3{-h, h, 0});
  const int apex = add_point(m, c + Vec3{0, 0, height});
  // Outward orientation for height > 0; reversed for a pyramid pointing down.
  auto tri = [&](int a, int b, int d, int face) {
    if (height > 0) add_tri(m, a, b, d, face, region);
    else add_tri(m, a, d, b, face, region);
  };
  tri(p0, p2, p1, first_face);
  tri(p0, p3, p2, first_face);
  tri(p0, p1, apex, first_face + 1);
  tri(p1, p2, apex, first_face + 2);
  tri(p2, p3, apex, first_face + 3);
  tri(p3, p0, apex, first_face + 4);
  return m;
}

Mesh box_with_hole(Vec3 lo, Vec3 hi, double f, int region, int first_face) {
  // Outer square ring on top and bottom, joined to the inner square by
  // trapezoids cut into two long triangles each: needle-shaped facets.
  Mesh m;
  const Vec3 c = 0.5 * (lo + hi);
  const double hx = 0.5 * (hi.x - lo.x), hy = 0.5 * (hi.y - lo.y);
  const Vec3 outer[4] = {{-hx, -hy, 0}, {hx, -hy, 0}, {hx, hy, 0}, {-hx, hy, 0}};
  int ob[4], ot[4], ib[4], it[4];
  for (int k = 0; k < 4; ++k) {
    const Vec3 o{c.x + outer[k].x, c.y + outer[k].y, 0};
    const Vec3 i{c.x + f * outer[k].x, c.y + f * outer[k].y, 0};
    ob[k] = add_point(m, {o.x, o.y, lo.z});
    ot[k] = add_point(m, {o.x, o.y, hi.z});
    ib[k] = add_point(m, {i.x, i.y, lo.z});
    it[k] = add_point(m, {i.x, i.y, hi.z});
  }
  for (int k = 0; k < 4; ++k) {
    const int n = (k + 1) % 4;
    // Bottom ring (normal -z) and top ring (normal +z).
    add_tri(m, ob[k], ib[n], ob[n], first_face, region);
    add_tri(m, ob[k], ib[k], ib[n], first_face, region);
    add_tri(m, ot[k], ot[n], it[n], first_face + 1, region);
    add_tri(m, ot[k], it[n], it[k], first_face + 1, region);
    // Outer side walls (normal outward) and hole walls (normal into the hole).
    add_tri(m, ob[k], ob[n], ot[n], first_face + 2 + k, region);
    add_tri(m, ob[k], ot[n], ot[k], first_face + 2 + k, region);
    add_tri(m, ib[k], it[n], ib[n], first_face + 6 + k, region);
    add_tri(m, ib[k], it[k], it[n], first_face + 6 + k, region);
  }
  return m;
}

void append(Mesh& a, const Mesh& b) {
  const int offset = static_cast<int>(a.points.size());
  a.points.insert(a.points.end(), b.points.begin(), b.points.end());
  for (Triangle t : b.triangles) {
    for (int& v : t.v) v += offset;
    a.triangles.push_back(t);
  }
  for (Tetrahedron t : b.tets) {
    for (int& v : t.v) v += offset;
    a.tets.push_back(t);
  }
}

void weld_exact(Mesh& m) {
  drop_unused_points(m);
  weld_coincident_points(m);
  drop_unused_points(m);
  m.point_size.clear();
}

void merge_coincident_facets(Mesh& m) {
  std::map<std::array<int, 3>, size_t> first;
  std::vector<bool> drop(m.triangles.size(), false);
  for (size_t f = 0; f < m.triangles.size(); ++f) {
    auto key = m.triangles[f].v;
    std::sort(key.begin(), key.end());
    auto [it, inserted] = first.emplace(key, f);
    if (inserted) continue;
    m.triangles[it->second].front = m.triangles[f].back;
    drop[f] = true;
  }
  std::vector<Triangle> kept;
  for (size_t f = 0; f < m.triangles.size(); ++f)
    if (!drop[f]) kept.push_back(m.triangles[f]);
  m.triangles = std::move(kept);
}

}  // namespace vd::shapes
