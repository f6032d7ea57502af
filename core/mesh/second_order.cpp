#include "mesh/second_order.h"

#include <algorithm>
#include <cstdint>
#include <unordered_map>
#include <vector>

#include "surface/edge_map.h"
#include "surface/surface_geometry.h"

namespace vd {
namespace {

// Edges in Mesh::TetMidNodes order, and the triangle's in TriMidNodes order.
constexpr int kTetEdge[6][2] = {{0, 1}, {1, 2}, {2, 0}, {0, 3}, {1, 3}, {2, 3}};
constexpr int kTriEdge[3][2] = {{0, 1}, {1, 2}, {2, 0}};

// Below this share of the straight element's Jacobian a curved element is
// too distorted for a solver's integration points; CalculiX stops on a
// non-positive Jacobian, and near zero the stiffness is already useless.
constexpr double kMinScaledJacobian = 0.1;

double det3(const Vec3& a, const Vec3& b, const Vec3& c) { return dot(a, cross(b, c)); }

// d x / d L_i of the quadratic tetrahedron, the L_i taken as independent.
Vec3 d_dl(const std::array<Vec3, 10>& x, const std::array<double, 4>& l, int i) {
  Vec3 g = (4 * l[i] - 1) * x[i];
  for (int e = 0; e < 6; ++e) {
    const int a = kTetEdge[e][0], b = kTetEdge[e][1];
    if (a == i) g = g + (4 * l[b]) * x[4 + e];
    if (b == i) g = g + (4 * l[a]) * x[4 + e];
  }
  return g;
}

// Points where a curved tetrahedron's Jacobian is checked: corners, edge
// mid-points, the centroid and the volume rule's points. det J is a cubic,
// so this is a check, not a proof; it is the one solvers make themselves at
// their integration points.
std::vector<std::array<double, 4>> jacobian_check_points() {
  std::vector<std::array<double, 4>> p;
  for (int i = 0; i < 4; ++i) {
    std::array<double, 4> l{};
    l[i] = 1;
    p.push_back(l);
  }
  for (const auto& e : kTetEdge) {
    std::array<double, 4> l{};
    l[e[0]] = l[e[1]] = 0.5;
    p.push_back(l);
  }
  p.push_back({0.25, 0.25, 0.25, 0.25});
  for (int i = 0; i < 4; ++i) {
    std::array<double, 4> l{1.0 / 6, 1.0 / 6, 1.0 / 6, 1.0 / 6};
    l[i] = 0.5;
    p.push_back(l);
  }
  return p;
}

}  // namespace

double quadratic_tet_jacobian(const std::array<Vec3, 10>& x, const std::array<double, 4>& l) {
  const Vec3 g0 = d_dl(x, l, 0);
  return det3(d_dl(x, l, 1) - g0, d_dl(x, l, 2) - g0, d_dl(x, l, 3) - g0);
}

double quadratic_tet_volume(const std::array<Vec3, 10>& x) {
  // Degree-3 rule on the tetrahedron: the centroid with weight -4/5 and four
  // points (1/2, 1/6, 1/6, 1/6) with 9/20 each.
  double v = -0.8 * quadratic_tet_jacobian(x, {0.25, 0.25, 0.25, 0.25});
  for (int i = 0; i < 4; ++i) {
    std::array<double, 4> l{1.0 / 6, 1.0 / 6, 1.0 / 6, 1.0 / 6};
    l[i] = 0.5;
    v += 0.45 * quadratic_tet_jacobian(x, l);
  }
  return v / 6;
}

double quadratic_triangle_area(const std::array<Vec3, 6>& x) {
  auto d_dl = [&](const std::array<double, 3>& l, int i) {
    Vec3 g = (4 * l[i] - 1) * x[i];
    for (int e = 0; e < 3; ++e) {
      const int a = kTriEdge[e][0], b = kTriEdge[e][1];
      if (a == i) g = g + (4 * l[b]) * x[3 + e];
      if (b == i) g = g + (4 * l[a]) * x[3 + e];
    }
    return g;
  };
  auto dA = [&](const std::array<double, 3>& l) {
    const Vec3 g0 = d_dl(l, 0);
    return norm(cross(d_dl(l, 1) - g0, d_dl(l, 2) - g0));
  };
  // Seven-point degree-5 rule on the triangle (Dunavant).
  const double a1 = 0.059715871789770, b1 = 0.470142064105115, w1 = 0.132394152788506;
  const double a2 = 0.797426985353087, b2 = 0.101286507323456, w2 = 0.125939180544827;
  double s = 0.225 * dA({1.0 / 3, 1.0 / 3, 1.0 / 3});
  s += w1 * (dA({a1, b1, b1}) + dA({b1, a1, b1}) + dA({b1, b1, a1}));
  s += w2 * (dA({a2, b2, b2}) + dA({b2, a2, b2}) + dA({b2, b2, a2}));
  return 0.5 * s;
}

std::array<Vec3, 10> tet_nodes(const Mesh& m, size_t t) {
  std::array<Vec3, 10> x;
  for (int i = 0; i < 4; ++i) x[i] = m.points[m.tets[t].v[i]];
  for (int e = 0; e < 6; ++e) x[4 + e] = m.points[m.tet_mid[t][e]];
  return x;
}

SecondOrderStats make_second_order(Mesh& m, const SurfaceGeometry* geometry) {
  SecondOrderStats stats;
  if (m.second_order()) return stats;
  std::unordered_map<std::uint64_t, int> node_of;
  std::vector<std::array<int, 2>> ends;  // per new node, its edge
  const int first = static_cast<int>(m.points.size());
  auto node = [&](int a, int b) {
    auto [it, added] = node_of.emplace(edge_key(a, b), first + static_cast<int>(ends.size()));
    if (added) ends.push_back({a, b});
    return it->second;
  };
  m.tet_mid.resize(m.tets.size());
  for (size_t t = 0; t < m.tets.size(); ++t)
    for (int e = 0; e < 6; ++e) m.tet_mid[t][e] = node(m.tets[t].v[kTetEdge[e][0]], m.tets[t].v[kTetEdge[e][1]]);
  m.triangle_mid.resize(m.triangles.size());
  for (size_t f = 0; f < m.triangles.size(); ++f)
    for (int e = 0; e < 3; ++e)
      m.triangle_mid[f][e] = node(m.triangles[f].v[kTriEdge[e][0]], m.triangles[f].v[kTriEdge[e][1]]);

  std::vector<Vec3> chord(ends.size());
  for (size_t k = 0; k < ends.size(); ++k) {
    chord[k] = 0.5 * (m.points[ends[k][0]] + m.points[ends[k][1]]);
    m.points.push_back(chord[k]);
    if (!m.point_size.empty())
      m.point_size.push_back(0.5 * (m.point_size[ends[k][0]] + m.point_size[ends[k][1]]));
  }
  stats.nodes = static_cast<long>(ends.size());

  // Faces of the facets around each surface edge, for the geometry.
  std::unordered_map<int, std::vector<int>> faces_at;
  for (size_t f = 0; f < m.triangles.size(); ++f)
    for (int e = 0; e < 3; ++e) faces_at[m.triangle_mid[f][e]].push_back(m.triangles[f].face);
  stats.surface_nodes = static_cast<long>(faces_at.size());
  if (!geometry) return stats;

  // In the facets' order, so that each node's face was met just before (the
  // geometry starts its search from there).
  std::vector<int> curved;
  std::vector<char> placed(ends.size(), 0);
  for (const TriMidNodes& mids : m.triangle_mid)
    for (const int n : mids) {
      if (placed[n - first]) continue;
      placed[n - first] = 1;
      const Vec3 c = chord[n - first];
      const Vec3 p = geometry->place_node(faces_at[n], m.points[ends[n - first][0]], m.points[ends[n - first][1]]);
      if (p.x != c.x || p.y != c.y || p.z != c.z) m.points[n] = p, curved.push_back(n);
    }
  std::sort(curved.begin(), curved.end());
  stats.on_geometry = static_cast<long>(curved.size());

  // Tetrahedra with a curved node, checked until none folds; each round only
  // straightens nodes, so it ends.
  std::unordered_map<int, std::vector<int>> tets_at;
  for (size_t t = 0; t < m.tets.size(); ++t)
    for (int n : m.tet_mid[t])
      if (std::binary_search(curved.begin(), curved.end(), n)) tets_at[n].push_back(static_cast<int>(t));
  std::vector<int> todo;
  for (const auto& [n, ts] : tets_at) todo.insert(todo.end(), ts.begin(), ts.end());
  std::sort(todo.begin(), todo.end());
  todo.erase(std::unique(todo.begin(), todo.end()), todo.end());
  const auto points = jacobian_check_points();
  auto is_curved = [&](int n) { return m.points[n].x != chord[n - first].x || m.points[n].y != chord[n - first].y ||
                                       m.points[n].z != chord[n - first].z; };
  while (!todo.empty()) {
    std::vector<int> next;
    for (int t : todo) {
      const std::array<Vec3, 10> x = tet_nodes(m, static_cast<size_t>(t));
      const double straight = det3(x[1] - x[0], x[2] - x[0], x[3] - x[0]);
      double worst = 1;
      for (const auto& l : points) worst = std::min(worst, quadratic_tet_jacobian(x, l) / straight);
      if (worst >= kMinScaledJacobian) continue;
      for (int n : m.tet_mid[t]) {
        if (n < first || !is_curved(n)) continue;
        m.points[n] = chord[n - first];
        ++stats.kept_straight;
        for (int u : tets_at[n])
          if (u != t) next.push_back(u);
      }
    }
    std::sort(next.begin(), next.end());
    next.erase(std::unique(next.begin(), next.end()), next.end());
    todo = std::move(next);
  }
  // The smallest value over what stayed curved, measured once at the end:
  // a neighbour's straightening can still change a tetrahedron checked earlier.
  for (const auto& [n, ts] : tets_at)
    for (int t : ts) {
      const std::array<Vec3, 10> x = tet_nodes(m, static_cast<size_t>(t));
      const double straight = det3(x[1] - x[0], x[2] - x[0], x[3] - x[0]);
      for (const auto& l : points)
        stats.min_scaled_jacobian = std::min(stats.min_scaled_jacobian, quadratic_tet_jacobian(x, l) / straight);
    }
  return stats;
}

void make_first_order(Mesh& m) {
  if (!m.second_order()) return;
  m.tet_mid.clear();
  m.triangle_mid.clear();
  std::vector<int> new_id(m.points.size(), -1);
  for (const Tetrahedron& t : m.tets)
    for (int v : t.v) new_id[v] = 0;
  for (const Triangle& t : m.triangles)
    for (int v : t.v) new_id[v] = 0;
  int next = 0;
  for (size_t i = 0; i < m.points.size(); ++i)
    if (new_id[i] == 0) {
      new_id[i] = next;
      m.points[next] = m.points[i];
      if (!m.point_size.empty()) m.point_size[next] = m.point_size[i];
      ++next;
    }
  m.points.resize(next);
  if (!m.point_size.empty()) m.point_size.resize(next);
  for (Tetrahedron& t : m.tets)
    for (int& v : t.v) v = new_id[v];
  for (Triangle& t : m.triangles)
    for (int& v : t.v) v = new_id[v];
}

}  // namespace vd
