#include "surface/size_refinement.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <map>
#include <queue>
#include <tuple>
#include <unordered_set>
#include <vector>

#include "surface/edge_map.h"
#include "surface/face_patches.h"

namespace vd {
namespace {

// A facet with a corner under this is narrow (see `waits` below).
const double kNarrowCorner = 20.0 * M_PI / 180.0;

// Replaces facet f = (.., p, q, ..) by the two facets on either side of the
// new vertex n on its edge {p, q}, keeping orientation, face and regions.
void split_facet(Mesh& m, int f, int p, int q, int n) {
  Triangle& t = m.triangles[f];
  int i = 0;
  while (!((t.v[i] == p && t.v[(i + 1) % 3] == q) || (t.v[i] == q && t.v[(i + 1) % 3] == p))) ++i;
  const int a = t.v[i], b = t.v[(i + 1) % 3], c = t.v[(i + 2) % 3];
  Triangle second = t;
  t.v = {a, n, c};
  second.v = {n, b, c};
  m.triangles.push_back(second);
}

Vec3 area_of(const Mesh& m, int a, int b, int c) { return cross(m.points[b] - m.points[a], m.points[c] - m.points[a]); }

// Flips inside each face towards the Delaunay criterion (the angles facing
// the shared edge sum to more than pi), only where the pair is convex in its
// average plane and folds by at most the ridge limit before and after.
// Returns the number of flips.
int flip_towards_delaunay(Mesh& m, double ridge_deg) {
  const double cos_limit = std::cos(ridge_deg * M_PI / 180.0);
  int total = 0;
  for (int pass = 0; pass < 8; ++pass) {
    const EdgeFacetPairs adjacency(m.triangles);
    const auto& pairs = adjacency.pairs;
    std::vector<char> touched(m.triangles.size(), 0);
    std::unordered_set<std::uint64_t> made;
    int flipped = 0;
    for (size_t i = 0; i + 1 < pairs.size(); ++i) {
      const std::uint64_t key = pairs[i].first;
      if (pairs[i + 1].first != key || (i > 0 && pairs[i - 1].first == key)) continue;
      if (i + 2 < pairs.size() && pairs[i + 2].first == key) continue;  // non-manifold
      const int f1 = pairs[i].second, f2 = pairs[i + 1].second;
      Triangle& t1 = m.triangles[f1];
      Triangle& t2 = m.triangles[f2];
      if (touched[f1] || touched[f2] || t1.face != t2.face || t1.front != t2.front || t1.back != t2.back) continue;
      // t1 = (p, q, r) in its cyclic order, t2 = (q, p, s).
      int k = 0;
      while (edge_key(t1.v[k], t1.v[(k + 1) % 3]) != key) ++k;
      const int p = t1.v[k], q = t1.v[(k + 1) % 3], r = t1.v[(k + 2) % 3];
      if (!has_directed_edge(t2, q, p)) continue;
      const int s = opposite_vertex(t2, p, q);
      if (r == s || adjacency.contains(edge_key(r, s)) || made.count(edge_key(r, s))) continue;
      const auto& P = m.points;
      if (corner_angle(P[r], P[p], P[q]) + corner_angle(P[s], P[q], P[p]) <= M_PI * (1 + 1e-9)) continue;
      const Vec3 o1 = area_of(m, p, q, r), o2 = area_of(m, q, p, s);
      const Vec3 n1 = area_of(m, s, q, r), n2 = area_of(m, r, p, s);
      const Vec3 n = normalized(normalized(o1) + normalized(o2));
      const double quad = dot(o1, n) + dot(o2, n);
      if (dot(o1, n) <= 0 || dot(o2, n) <= 0 || dot(n1, n) <= 0.02 * quad || dot(n2, n) <= 0.02 * quad) continue;
      if (dot(normalized(o1), normalized(o2)) < cos_limit || dot(normalized(n1), normalized(n2)) < cos_limit) continue;
      t1.v = {s, q, r};
      t2.v = {r, p, s};
      touched[f1] = touched[f2] = 1;
      made.insert(edge_key(r, s));
      ++flipped;
    }
    total += flipped;
    if (flipped == 0) break;
  }
  return total;
}

}  // namespace

std::vector<double> graded_edge_sizes(const Mesh& m, double gradation) {
  std::vector<std::vector<std::pair<int, double>>> around(m.points.size());
  std::vector<double> h(m.points.size(), std::numeric_limits<double>::infinity());
  for (const Triangle& t : m.triangles)
    for (int e = 0; e < 3; ++e) {
      const int a = t.v[e], b = t.v[(e + 1) % 3];
      const double l = norm(m.points[a] - m.points[b]);
      around[a].emplace_back(b, l);
      h[a] = std::min(h[a], l);
    }
  using Item = std::pair<double, int>;
  std::priority_queue<Item, std::vector<Item>, std::greater<Item>> queue;
  for (size_t v = 0; v < h.size(); ++v)
    if (std::isfinite(h[v])) queue.emplace(h[v], static_cast<int>(v));
  while (!queue.empty()) {
    const auto [hv, v] = queue.top();
    queue.pop();
    if (hv > h[v]) continue;
    for (const auto& [u, l] : around[v])
      if (hv + gradation * l < h[u]) {
        h[u] = hv + gradation * l;
        queue.emplace(h[u], u);
      }
  }
  for (double& x : h)
    if (!std::isfinite(x)) x = 0;
  return h;
}

std::vector<char> sharp_face_corners(const Mesh& m, double limit_deg) {
  // The angle of each face at each of its vertices: the sum of its facets'
  // corners there (under 360 for a vertex on the face's border).
  std::map<std::pair<int, int>, double> angle;  // (vertex, face)
  for (const Triangle& t : m.triangles)
    for (int k = 0; k < 3; ++k) {
      angle[{t.v[k], t.face}] += corner_angle(m.points[t.v[k]], m.points[t.v[(k + 1) % 3]], m.points[t.v[(k + 2) % 3]]);
    }
  std::vector<char> sharp(m.points.size(), 0);
  const double limit = limit_deg * M_PI / 180.0;
  for (const auto& [key, a] : angle)
    if (a < limit) sharp[key.first] = 1;
  return sharp;
}

SizeRefinementStats refine_surface_to_size(Mesh& m, double size, GradedSizes* graded) {
  SizeRefinementStats stats;
  const bool per_vertex = !m.point_size.empty();
  if (size <= 0 && !per_vertex && !graded) return stats;
  auto limit = [&](int a, int b) {
    double h = size > 0 ? kLongestEdgeOverSize * size : std::numeric_limits<double>::infinity();
    if (per_vertex && m.point_size[a] > 0 && m.point_size[b] > 0)
      h = std::min(h, kLongestEdgeOverSize * 0.5 * (m.point_size[a] + m.point_size[b]));
    if (!graded || graded->at_sharp_corner(a) || graded->at_sharp_corner(b)) return h;
    if (graded->size[a] > 0 && graded->size[b] > 0)
      h = std::min(h, graded->factor * 0.5 * (graded->size[a] + graded->size[b]));
    if (graded->in_space) h = std::min(h, graded->factor * graded->in_space(0.5 * (m.points[a] + m.points[b])));
    return h;
  };
  // Each pass splits every long edge whose facets no earlier split of the
  // pass touched; halving lengths, the passes are logarithmic in size ratio.
  for (bool again = true; again; ++stats.passes) {
    again = false;
    if (graded && graded->flip_ridge_deg > 0) stats.flips += flip_towards_delaunay(m, graded->flip_ridge_deg);
    // Sorted pairs, not an EdgeMap: a hash map of vectors, one allocation per
    // edge and pass, was most of this phase (0.53 -> 0.13 s on a sphere
    // split to 125k facets).
    const EdgeFacetPairs adjacency(m.triangles);
    const auto& pairs = adjacency.pairs;
    struct LongEdge {
      double length;
      std::uint64_t key;
      size_t first, last;  // its run in `pairs`
      bool on_border;      // between two faces, or not shared by exactly two facets
      bool operator>(const LongEdge& o) const { return std::tie(length, key) > std::tie(o.length, o.key); }
    };
    std::vector<LongEdge> long_edges;
    for (size_t i = 0, j; i < pairs.size(); i = j) {
      for (j = i + 1; j < pairs.size() && pairs[j].first == pairs[i].first; ++j) {
      }
      const std::uint64_t key = pairs[i].first;
      const int a = static_cast<int>(key >> 32), b = static_cast<int>(key & 0xffffffffu);
      const double l = norm(m.points[a] - m.points[b]);
      if (l <= limit(a, b)) continue;
      bool on_border = j - i != 2;
      if (!on_border) {
        const Triangle& t1 = m.triangles[pairs[i].second];
        const Triangle& t2 = m.triangles[pairs[i + 1].second];
        on_border = t1.face != t2.face || t1.front != t2.front || t1.back != t2.back;
      }
      long_edges.push_back({l, key, i, j, on_border});
    }
    // An edge inside a face waits while one of its facets is narrow (a
    // corner under 20 deg) and has a long edge on the face's border: split
    // first, the border's mid-points let the flips turn the inner edge,
    // where its own mid-point would have stood inside a narrow face, off its
    // borders (a 1 x 0.017 end face of a 1 deg wedge got a vertex at
    // mid-height, which split the wedge's angle: 1 -> 0.5 deg).
    std::vector<char> waits(m.triangles.size(), 0);
    for (const LongEdge& edge : long_edges)
      if (edge.on_border)
        for (size_t i = edge.first; i < edge.last; ++i) {
          const int f = pairs[i].second;
          waits[f] = smallest_corner_angle(m.points, m.triangles[f]) < kNarrowCorner;
        }
    // Longest first, ties by key.
    std::sort(long_edges.begin(), long_edges.end(), std::greater<>());
    std::vector<char> touched(m.triangles.size(), 0);
    for (const LongEdge& edge : long_edges) {
      bool clear = true;
      for (size_t i = edge.first; i < edge.last; ++i)
        clear = clear && !touched[pairs[i].second] && (edge.on_border || !waits[pairs[i].second]);
      if (!clear) {
        again = true;
        continue;
      }
      const std::uint64_t key = edge.key;
      const int a = static_cast<int>(key >> 32), b = static_cast<int>(key & 0xffffffffu);
      const int n = static_cast<int>(m.points.size());
      m.points.push_back(0.5 * (m.points[a] + m.points[b]));
      if (per_vertex) m.point_size.push_back(0.5 * (m.point_size[a] + m.point_size[b]));
      if (graded) {
        const double half = 0.5 * norm(m.points[a] - m.points[b]);
        double h = std::min(graded->size[a], graded->size[b]) + graded->gradation * half;
        if (graded->in_space) h = std::min(h, graded->in_space(m.points[n]));
        graded->size.push_back(h);
      }
      for (size_t i = edge.first; i < edge.last; ++i) {
        const int f = pairs[i].second;
        split_facet(m, f, a, b, n);
        touched[f] = 1;
      }
      touched.resize(m.triangles.size(), 1);
      ++stats.splits;
      again = true;
    }
  }
  if (graded && graded->flip_ridge_deg > 0) stats.flips += flip_towards_delaunay(m, graded->flip_ridge_deg);
  return stats;
}

}  // namespace vd
