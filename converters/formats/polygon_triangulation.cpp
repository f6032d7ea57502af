#include "polygon_triangulation.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <unordered_map>
#include <unordered_set>

#include "geometry/predicates.h"

namespace vd::io::detail {
namespace {

struct P2 {
  double x, y;
};

double cross2(P2 o, P2 a, P2 b) { return (a.x - o.x) * (b.y - o.y) - (a.y - o.y) * (b.x - o.x); }

double signed_area(const std::vector<P2>& p) {
  double a = 0;
  for (size_t i = 0, j = p.size() - 1; i < p.size(); j = i++) a += p[j].x * p[i].y - p[i].x * p[j].y;
  return a / 2;
}

// A polygon's normal by Newell's sums: its length is twice the area, its
// direction the turn of the polygon's order, also when it is not convex.
Vec3 newell_normal(const std::vector<Vec3>& points, const std::vector<int>& polygon) {
  Vec3 normal{0, 0, 0};
  for (size_t i = 0, j = polygon.size() - 1; i < polygon.size(); j = i++) {
    const Vec3 a = points[static_cast<size_t>(polygon[j])], b = points[static_cast<size_t>(polygon[i])];
    normal = normal + Vec3{(a.y - b.y) * (a.z + b.z), (a.z - b.z) * (a.x + b.x), (a.x - b.x) * (a.y + b.y)};
  }
  return normal;
}

bool inside(const std::vector<P2>& poly, P2 q) {
  bool in = false;
  for (size_t i = 0, j = poly.size() - 1; i < poly.size(); j = i++) {
    const P2 a = poly[i], b = poly[j];
    if ((a.y > q.y) != (b.y > q.y) && q.x < (b.x - a.x) * (q.y - a.y) / (b.y - a.y) + a.x) in = !in;
  }
  return in;
}

// Proper crossing of segments ab and cd (touching at ends does not count).
bool crosses(P2 a, P2 b, P2 c, P2 d) {
  const double d1 = cross2(a, b, c), d2 = cross2(a, b, d), d3 = cross2(c, d, a), d4 = cross2(c, d, b);
  return ((d1 > 0 && d2 < 0) || (d1 < 0 && d2 > 0)) && ((d3 > 0 && d4 < 0) || (d3 < 0 && d4 > 0));
}

// Inside or on the boundary: a vertex on an ear's closing diagonal blocks
// it. Counted free, the L-shaped cap's reflex corner on the diagonal of its
// first ear let the next ear reach outside the polygon (2026-11-30).
bool in_or_on_triangle(P2 a, P2 b, P2 c, P2 q) {
  return cross2(a, b, q) >= 0 && cross2(b, c, q) >= 0 && cross2(c, a, q) >= 0;
}

// Ear clipping of a counter-clockwise loop (may touch itself at bridge
// vertices); falls back to a fan when no ear is left.
void clip_ears(std::vector<int> loop, const std::vector<P2>& at, std::vector<std::array<int, 3>>& out) {
  auto pos = [&](int i) { return at[static_cast<size_t>(i)]; };
  size_t guard = 0;
  while (loop.size() > 3) {
    const size_t n = loop.size();
    bool clipped = false;
    for (size_t i = 0; i < n && !clipped; ++i) {
      const int a = loop[(i + n - 1) % n], b = loop[i], c = loop[(i + 1) % n];
      const P2 pa = pos(a), pb = pos(b), pc = pos(c);
      if (cross2(pa, pb, pc) <= 0) continue;  // reflex or flat
      bool empty = true;
      for (size_t j = 0; j < n && empty; ++j) {
        const int q = loop[j];
        const P2 pq = pos(q);
        if ((pq.x == pa.x && pq.y == pa.y) || (pq.x == pb.x && pq.y == pb.y) || (pq.x == pc.x && pq.y == pc.y))
          continue;
        empty = !in_or_on_triangle(pa, pb, pc, pq);
      }
      if (!empty) continue;
      out.push_back({a, b, c});
      loop.erase(loop.begin() + static_cast<std::ptrdiff_t>(i));
      clipped = true;
    }
    if (!clipped || ++guard > 4 * at.size() + 16) {
      // Degenerate (collinear or self-touching, or a vertex on every ear's
      // diagonal): finish as a fan.
      for (size_t i = 1; i + 1 < loop.size(); ++i) out.push_back({loop[0], loop[i], loop[i + 1]});
      return;
    }
  }
  if (loop.size() == 3) out.push_back({loop[0], loop[1], loop[2]});
}

// Lawson's flips of the edges that are not the polygons' own, until every
// one is locally Delaunay in the facet's plane: the constrained Delaunay
// triangulation of the facet. Ear clipping leaves fans of needles (a
// polygon with many points on a long side), and a pair of coplanar facets
// whose circle holds the other's apex is never a face of the Delaunay
// tetrahedralization: with --no-flips
// nothing inside a face changes, and `tetgen_example.poly` ended in exit 4
// (1,776 facets missing after 12 passes) on its clipped facets. The
// triangles are counter-clockwise in `at`; a triangulation that is not
// (the fan of a polygon clipping could not finish) is left as it is.
void flip_to_delaunay(std::vector<std::array<int, 3>>& tris, const std::vector<Vec3>& points,
                      const std::vector<P2>& at, const std::vector<const std::vector<int>*>& polys) {
  const auto key = [](int a, int b) {
    return (static_cast<std::uint64_t>(static_cast<std::uint32_t>(a)) << 32) | static_cast<std::uint32_t>(b);
  };
  const auto p = [&](int i) { return at[static_cast<size_t>(i)]; };
  const auto P = [&](int i) { return points[static_cast<size_t>(i)]; };
  const auto turn = [&](int a, int b, int c) { return orientation_2d(p(a).x, p(a).y, p(b).x, p(b).y, p(c).x, p(c).y); };
  std::unordered_set<std::uint64_t> fixed;  // the polygons' edges, both ways
  for (const auto* poly : polys)
    for (size_t k = 0; k < poly->size(); ++k) {
      const int a = (*poly)[k], b = (*poly)[(k + 1) % poly->size()];
      fixed.insert(key(a, b));
      fixed.insert(key(b, a));
    }
  std::unordered_map<std::uint64_t, int> owner;  // directed edge -> its triangle
  for (size_t t = 0; t < tris.size(); ++t) {
    const auto& v = tris[t];
    if (turn(v[0], v[1], v[2]) <= 0) return;
    for (int k = 0; k < 3; ++k)
      if (!owner.emplace(key(v[k], v[(k + 1) % 3]), static_cast<int>(t)).second) return;
  }
  const auto apex = [&](int t, int a, int b) {  // the corner of t off its edge a -> b
    for (int c : tris[static_cast<size_t>(t)])
      if (c != a && c != b) return c;
    return -1;
  };
  std::vector<std::pair<int, int>> todo;
  for (const auto& [k, t] : owner) {
    const int a = static_cast<int>(k >> 32), b = static_cast<int>(k & 0xffffffffu);
    if (a < b && !fixed.count(k) && owner.count(key(b, a))) todo.push_back({a, b});
  }
  std::sort(todo.begin(), todo.end());  // the map's order is not the same everywhere
  // Each flip lowers the lifted triangulation; the guard only bounds a bug.
  for (size_t flips = 0; !todo.empty() && flips < 4 * tris.size() * tris.size() + 64;) {
    const auto [a, b] = todo.back();
    todo.pop_back();
    const auto ab = owner.find(key(a, b)), ba = owner.find(key(b, a));
    if (ab == owner.end() || ba == owner.end()) continue;  // flipped away meanwhile
    const int t1 = ab->second, t2 = ba->second;
    const int c = apex(t1, a, b), d = apex(t2, b, a);
    // In the facet's plane, not in the projection, which is no similarity
    // (a tilted facet's circles are ellipses there): the circle of (a, b, c)
    // is the equator of their smallest sphere.
    if (side_of_equatorial_sphere(P(a), P(b), P(c), P(d)) != SphereSide::inside) continue;
    if (turn(a, d, c) <= 0 || turn(d, b, c) <= 0) continue;
    owner.erase(ab);
    owner.erase(key(b, a));
    tris[static_cast<size_t>(t1)] = {a, d, c};
    tris[static_cast<size_t>(t2)] = {d, b, c};
    owner[key(a, d)] = owner[key(d, c)] = owner[key(c, a)] = t1;
    owner[key(d, b)] = owner[key(b, c)] = owner[key(c, d)] = t2;
    ++flips;
    for (const auto& [x, y] : {std::pair{a, d}, std::pair{d, b}, std::pair{b, c}, std::pair{c, a}})
      if (!fixed.count(key(x, y)) && owner.count(key(y, x))) todo.push_back({std::min(x, y), std::max(x, y)});
  }
}

}  // namespace

namespace {

// The facet with its own points (indices into `points` are local).
std::vector<std::array<int, 3>> triangulate_local(const std::vector<Vec3>& points,
                                                  const std::vector<std::vector<int>>& polygons,
                                                  const std::vector<Vec3>& holes) {
  std::vector<std::array<int, 3>> out;
  std::vector<const std::vector<int>*> polys;
  for (const auto& p : polygons)
    if (p.size() >= 3) polys.push_back(&p);
  if (polys.empty()) return out;
  // Facet normal from the first polygon with area.
  Vec3 normal{0, 0, 0};
  for (const auto* p : polys)
    if (norm(normal = newell_normal(points, *p)) > 0) break;
  if (polys.size() == 1 && polys[0]->size() == 3) {
    out.push_back({(*polys[0])[0], (*polys[0])[1], (*polys[0])[2]});
    return out;
  }
  // Project by dropping the normal's largest axis; keep orientation.
  int axis = 0;
  for (int k = 1; k < 3; ++k)
    if (std::abs(normal[k]) > std::abs(normal[axis])) axis = k;
  const int u = (axis + 1) % 3, v = (axis + 2) % 3;
  const double flip = normal[axis] < 0 ? -1.0 : 1.0;
  auto project = [&](const Vec3& p) { return P2{p[u], flip * p[v]}; };
  std::vector<P2> at(points.size());
  for (const auto* p : polys)
    for (int i : *p) at[static_cast<size_t>(i)] = project(points[static_cast<size_t>(i)]);

  const size_t n = polys.size();
  std::vector<std::vector<P2>> shape(n);
  std::vector<double> area(n);
  for (size_t i = 0; i < n; ++i) {
    for (int k : *polys[i]) shape[i].push_back(at[static_cast<size_t>(k)]);
    area[i] = std::abs(signed_area(shape[i]));
  }
  // Parent: the smallest polygon containing this one.
  std::vector<int> parent(n, -1);
  for (size_t i = 0; i < n; ++i) {
    // A vertex of i that is not on j's boundary decides containment.
    for (size_t j = 0; j < n; ++j) {
      if (i == j || area[j] <= area[i]) continue;
      bool in = false;
      for (int k : *polys[i]) {
        if (std::find(polys[j]->begin(), polys[j]->end(), k) != polys[j]->end()) continue;
        in = inside(shape[j], at[static_cast<size_t>(k)]);
        break;
      }
      if (in && (parent[i] < 0 || area[j] < area[static_cast<size_t>(parent[i])])) parent[i] = static_cast<int>(j);
    }
  }
  std::vector<P2> hole_points;
  for (const Vec3& h : holes) hole_points.push_back(project(h));
  for (size_t i = 0; i < n; ++i) {
    std::vector<size_t> children;
    for (size_t j = 0; j < n; ++j)
      if (parent[j] == static_cast<int>(i)) children.push_back(j);
    bool is_hole = false;
    for (const P2& h : hole_points) {
      if (!inside(shape[i], h)) continue;
      bool in_child = false;
      for (size_t c : children) in_child |= inside(shape[c], h);
      is_hole |= !in_child;
    }
    if (is_hole) continue;
    // Outer loop counter-clockwise, children clockwise, bridged in order of
    // their rightmost vertex.
    std::vector<int> loop = *polys[i];
    if (signed_area(shape[i]) < 0) std::reverse(loop.begin(), loop.end());
    std::sort(children.begin(), children.end(), [&](size_t a, size_t b) {
      double ma = -1e300, mb = -1e300;
      for (const P2& p : shape[a]) ma = std::max(ma, p.x);
      for (const P2& p : shape[b]) mb = std::max(mb, p.x);
      return ma > mb;
    });
    std::vector<std::pair<P2, P2>> edges;  // every boundary edge, for visibility
    auto add_edges = [&](const std::vector<int>& l) {
      for (size_t k = 0; k < l.size(); ++k)
        edges.push_back({at[static_cast<size_t>(l[k])], at[static_cast<size_t>(l[(k + 1) % l.size()])]});
    };
    add_edges(loop);
    for (size_t c : children) add_edges(*polys[c]);
    for (size_t c : children) {
      std::vector<int> hole = *polys[c];
      if (signed_area(shape[c]) > 0) std::reverse(hole.begin(), hole.end());
      size_t hr = 0;
      for (size_t k = 1; k < hole.size(); ++k)
        if (at[static_cast<size_t>(hole[k])].x > at[static_cast<size_t>(hole[hr])].x) hr = k;
      const P2 h = at[static_cast<size_t>(hole[hr])];
      // The nearest loop vertex that the hole vertex sees.
      std::vector<size_t> cand(loop.size());
      for (size_t k = 0; k < loop.size(); ++k) cand[k] = k;
      auto dist = [&](size_t k) {
        const P2 p = at[static_cast<size_t>(loop[k])];
        return (p.x - h.x) * (p.x - h.x) + (p.y - h.y) * (p.y - h.y);
      };
      std::sort(cand.begin(), cand.end(), [&](size_t a, size_t b) { return dist(a) < dist(b); });
      size_t best = cand.front();
      for (size_t k : cand) {
        const P2 p = at[static_cast<size_t>(loop[k])];
        bool blocked = false;
        for (const auto& e : edges) blocked |= crosses(h, p, e.first, e.second);
        if (!blocked) {
          best = k;
          break;
        }
      }
      // loop[..best], hole from hr around back to hr, loop[best..].
      std::vector<int> merged(loop.begin(), loop.begin() + static_cast<std::ptrdiff_t>(best) + 1);
      for (size_t k = 0; k <= hole.size(); ++k) merged.push_back(hole[(hr + k) % hole.size()]);
      merged.insert(merged.end(), loop.begin() + static_cast<std::ptrdiff_t>(best), loop.end());
      loop.swap(merged);
    }
    clip_ears(loop, at, out);
  }
  flip_to_delaunay(out, points, at, polys);
  // Turn every triangle like the facet's normal.
  for (auto& t : out) {
    const Vec3 a = points[static_cast<size_t>(t[0])];
    const Vec3 nt = cross(points[static_cast<size_t>(t[1])] - a, points[static_cast<size_t>(t[2])] - a);
    if (dot(nt, normal) < 0) std::swap(t[1], t[2]);
  }
  return out;
}

}  // namespace

std::vector<std::array<int, 3>> triangulate_facet(const std::vector<Vec3>& points,
                                                  const std::vector<std::vector<int>>& polygons,
                                                  const std::vector<Vec3>& holes) {
  if (polygons.size() == 1 && polygons[0].size() == 3) return {{polygons[0][0], polygons[0][1], polygons[0][2]}};
  // Work on the facet's own points so the cost does not grow with the PLC.
  std::vector<int> global;
  std::vector<std::vector<int>> local = polygons;
  for (auto& p : local)
    for (int& i : p) {
      auto it = std::find(global.begin(), global.end(), i);
      if (it == global.end()) it = global.insert(global.end(), i);
      i = static_cast<int>(it - global.begin());
    }
  std::vector<Vec3> pts;
  for (int i : global) pts.push_back(points[static_cast<size_t>(i)]);
  auto out = triangulate_local(pts, local, holes);
  for (auto& t : out)
    for (int& i : t) i = global[static_cast<size_t>(i)];
  return out;
}

std::vector<std::array<int, 3>> fan(const std::vector<int>& polygon) {
  std::vector<std::array<int, 3>> out;
  for (size_t j = 1; j + 1 < polygon.size(); ++j) out.push_back({polygon[0], polygon[j], polygon[j + 1]});
  return out;
}

std::vector<std::array<int, 3>> strip_triangles(const int* strip, size_t count) {
  std::vector<std::array<int, 3>> out;
  for (size_t j = 0; j + 2 < count; ++j) {
    const std::array<int, 3> t = j % 2 == 0 ? std::array<int, 3>{strip[j], strip[j + 1], strip[j + 2]}
                                            : std::array<int, 3>{strip[j + 1], strip[j], strip[j + 2]};
    if (t[0] != t[1] && t[1] != t[2] && t[0] != t[2]) out.push_back(t);
  }
  return out;
}

std::vector<std::array<int, 3>> triangulate_polygon(const std::vector<Vec3>& points, const std::vector<int>& polygon) {
  const size_t n = polygon.size();
  const auto at = [&](size_t i) { return points[static_cast<size_t>(polygon[i % n])]; };
  const Vec3 normal = newell_normal(points, polygon);
  bool convex = true;
  for (size_t i = 0; i < n && convex; ++i) convex = dot(cross(at(i + 1) - at(i), at(i + 2) - at(i + 1)), normal) > 0;
  if (!convex && n > 3) return triangulate_facet(points, {polygon}, {});
  return fan(polygon);
}

}  // namespace vd::io::detail
