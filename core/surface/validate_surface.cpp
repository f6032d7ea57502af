#include "surface/validate_surface.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/box_intersection_d.h>
#include <CGAL/intersections.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <optional>
#include <sstream>

#include "mesh/error.h"
#include "mesh/parallel.h"
#include "surface/edge_map.h"

namespace vd {
namespace {

using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using P3 = K::Point_3;

P3 cgal(const Vec3& p) { return {p.x, p.y, p.z}; }

std::string list_facets(const std::vector<int>& ids, size_t max_shown = 10) {
  std::ostringstream s;
  for (size_t i = 0; i < ids.size() && i < max_shown; ++i) s << (i ? ", " : "") << ids[i];
  if (ids.size() > max_shown) s << ", ... (" << ids.size() << " in all)";
  return s.str();
}

constexpr double kSmallestExtent = 1e-60, kLargestCoordinate = 1e60;

}  // namespace

void check_tags_and_sizes(const Mesh& m) {
  for (size_t f = 0; f < m.triangles.size(); ++f) {
    for (const auto& [side, r] : {std::pair{"front", m.triangles[f].front}, std::pair{"back", m.triangles[f].back}})
      if (r < kUnknownRegion || r > kLargestRegionId)
        throw InputError("facet " + std::to_string(f) + " names region " + std::to_string(r) + " on its " + side +
                         " side; a region is 0 (the exterior), 1 to " + std::to_string(kLargestRegionId) +
                         ", or -1 (not known)");
    if (m.triangles[f].face < kNoFace)
      throw InputError("facet " + std::to_string(f) + " has face id " + std::to_string(m.triangles[f].face) +
                       "; a face id is 0 or more, or -1 (none)");
  }
  // One size per vertex, or none: a shorter list was read past (and written
  // past) by the steps after, from C++ (2026-11-30; Python checks its arrays).
  if (!m.point_size.empty() && m.point_size.size() != m.points.size())
    throw InputError("the surface has " + std::to_string(m.point_size.size()) + " vertex sizes for " +
                     std::to_string(m.points.size()) + " vertices (one per vertex, or none)");
  // Facet corners that are no vertex, likewise.
  for (size_t f = 0; f < m.triangles.size(); ++f)
    for (const int v : m.triangles[f].v)
      if (v < 0 || static_cast<size_t>(v) >= m.points.size())
        throw InputError("facet " + std::to_string(f) + " has corner " + std::to_string(v) + ", which is no vertex (" +
                         std::to_string(m.points.size()) + " vertices)");
  for (size_t v = 0; v < m.point_size.size(); ++v)
    if (!(m.point_size[v] >= 0) || !std::isfinite(m.point_size[v])) {
      std::ostringstream s;
      s << "vertex " << v << " has size " << m.point_size[v] << "; a vertex's size is positive, or 0 (none)";
      throw InputError(s.str());
    }
  for (size_t i = 0; i < m.region_points.size(); ++i) {
    const RegionPoint& r = m.region_points[i];
    if (!std::isfinite(r.at.x) || !std::isfinite(r.at.y) || !std::isfinite(r.at.z))
      throw InputError("region point " + std::to_string(i) + " has a non-finite coordinate");
    if (r.region < 0 || r.region > kLargestRegionId)
      throw InputError("region point " + std::to_string(i) + " names region " + std::to_string(r.region) +
                       "; a region point names 1 to " + std::to_string(kLargestRegionId) + ", or 0 (a hole)");
  }
}

namespace {

void check_indices_and_coordinates(const Mesh& m) {
  if (m.triangles.empty()) throw InputError("the surface has no facets");
  for (size_t i = 0; i < m.points.size(); ++i) {
    const Vec3& p = m.points[i];
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
      throw InputError("vertex " + std::to_string(i) + " has a non-finite coordinate");
  }
  // Squared lengths and volumes over- or underflow near 1e150 and 1e-150:
  // a tetrahedron 1e-200 or 1e160 across ran without end (the refinement
  // splitting edges of infinite length; the lattice stepping by nothing).
  // Fourth powers do near 1e-80 and 1e77: a unit box scaled by 1e-85 came
  // out with 46 tetrahedra and 29 % of its volume gone, by 1e80 with 59
  // and slivers of 0.02 degrees, where 1e-80 to 1e75 give its 12 (a Python
  // tester, 2026-11-30). 1e-60 to 1e60 leaves room for features far under
  // the span.
  const Box box = bounding_box(m.points);
  double extent = 0, reach = 0;
  for (int k = 0; k < 3; ++k) {
    extent = std::max(extent, box.hi[k] - box.lo[k]);
    reach = std::max({reach, std::abs(box.lo[k]), std::abs(box.hi[k])});
  }
  if (!m.points.empty() && (!(extent >= kSmallestExtent) || !(reach <= kLargestCoordinate))) {
    std::ostringstream s;
    s << "the surface spans " << extent << " and reaches " << reach << " from the origin; vdmesh's arithmetic"
      << " needs a span of at least " << kSmallestExtent << " and coordinates of at most " << kLargestCoordinate
      << " (scale the model, or give it other units)";
    throw InputError(s.str());
  }
  const int n = static_cast<int>(m.points.size());
  for (size_t f = 0; f < m.triangles.size(); ++f)
    for (int v : m.triangles[f].v)
      if (v < 0 || v >= n)
        throw InputError("facet " + std::to_string(f) + " refers to vertex " + std::to_string(v) +
                         ", which does not exist (" + std::to_string(n) + " vertices)");
}

void check_degenerate(const Mesh& m) {
  std::vector<int> bad;
  for (size_t f = 0; f < m.triangles.size(); ++f) {
    const auto& v = m.triangles[f].v;
    if (v[0] == v[1] || v[1] == v[2] || v[0] == v[2] ||
        CGAL::collinear(cgal(m.points[v[0]]), cgal(m.points[v[1]]), cgal(m.points[v[2]])))
      bad.push_back(static_cast<int>(f));
  }
  if (!bad.empty())
    throw InputError("degenerate facets (repeated or collinear vertices): " + list_facets(bad));
}

void check_duplicates(const Mesh& m) {
  // Sorted (vertex triple, facet) pairs: equal triples lie together, each
  // run in facet order (a std::map of the triples was a twentieth of a
  // surface-only run on the bunny).
  std::vector<std::pair<std::array<int, 3>, int>> keyed(m.triangles.size());
  for (size_t f = 0; f < m.triangles.size(); ++f) {
    auto key = m.triangles[f].v;
    std::sort(key.begin(), key.end());
    keyed[f] = {key, static_cast<int>(f)};
  }
  std::sort(keyed.begin(), keyed.end());
  // Each repeat with the first facet of its triple, in the repeats' order.
  std::vector<std::pair<int, int>> repeats;  // (repeat, first)
  for (size_t i = 1, first = 0; i < keyed.size(); ++i) {
    if (keyed[i].first != keyed[first].first) {
      first = i;
      continue;
    }
    repeats.emplace_back(keyed[i].second, keyed[first].second);
  }
  if (repeats.empty()) return;
  std::sort(repeats.begin(), repeats.end());
  std::vector<int> bad;
  for (const auto& [repeat, first] : repeats) {
    bad.push_back(first);
    bad.push_back(repeat);
  }
  throw InputError("duplicate facets (same three vertices): " + list_facets(bad));
}

// Across a manifold edge the two facets must run the edge in opposite
// directions when their regions match as given (or are unknown), and in the
// same direction when the tags say one of them is turned over.
void check_orientation(const Mesh& m, const EdgeMap& edges, SurfaceCheck& out) {
  for (const auto& [key, list] : edges.all()) {
    if (list.size() == 1) {
      out.open_edges.push_back(edge_of_key(key));
      continue;
    }
    if (list.size() > 2) {
      ++out.non_manifold_edges;
      continue;
    }
    const auto [a, b] = edge_of_key(key);
    const Triangle& t1 = m.triangles[list[0]];
    const Triangle& t2 = m.triangles[list[1]];
    const bool same_direction = has_directed_edge(t1, a, b) == has_directed_edge(t2, a, b);
    // An unknown side (kUnknownRegion) agrees with any region; a facet
    // turned over needs its regions known and swapped.
    const auto agree = [](int r, int s) { return r == s || r == kUnknownRegion || s == kUnknownRegion; };
    const bool tagged = t1.front != kUnknownRegion || t1.back != kUnknownRegion || t2.front != kUnknownRegion ||
                        t2.back != kUnknownRegion;
    bool consistent;
    if (same_direction)
      consistent = t1.front == t2.back && t1.back == t2.front && t1.front != kUnknownRegion &&
                   t1.back != kUnknownRegion;
    else
      consistent = agree(t1.front, t2.front) && agree(t1.back, t2.back);
    if (!consistent) {
      // Tagged facets that run the edge in opposite directions are turned
      // alike: what is wrong is a region, not the orientation.
      std::ostringstream s;
      const auto tags = [](const Triangle& t) {
        return "front " + std::to_string(t.front) + ", back " + std::to_string(t.back);
      };
      if (!tagged)
        s << "inconsistent orientation: facets " << list[0] << " and " << list[1] << " run edge (" << a << ", " << b
          << ") in the same direction (one of them is turned over)";
      else if (same_direction)
        s << "inconsistent orientation: facets " << list[0] << " (" << tags(t1) << ") and " << list[1] << " ("
          << tags(t2) << ") run edge (" << a << ", " << b
          << ") in the same direction, so one of them is turned over, but their regions are not swapped";
      else
        s << "region tags disagree: facets " << list[0] << " (" << tags(t1) << ") and " << list[1] << " ("
          << tags(t2) << ") are turned alike across edge (" << a << ", " << b
          << "), the only two facets there, so the same regions lie in front of them and behind them";
      throw InputError(s.str());
    }
  }
  std::sort(out.open_edges.begin(), out.open_edges.end());
}

int shared_vertices(const Triangle& a, const Triangle& b, int* shared) {
  int n = 0;
  for (int u : a.v)
    for (int w : b.v)
      if (u == w) shared[n++] = u;
  return n;
}

// Do two facets meet in more than the vertices or edge they share?
bool facets_intersect(const Mesh& m, const Triangle& t1, const Triangle& t2) {
  int shared[3];
  const int n = shared_vertices(t1, t2, shared);
  auto p = [&](int v) { return cgal(m.points[v]); };
  const K::Triangle_3 T1(p(t1.v[0]), p(t1.v[1]), p(t1.v[2]));
  const K::Triangle_3 T2(p(t2.v[0]), p(t2.v[1]), p(t2.v[2]));
  if (n == 0) return CGAL::do_intersect(T1, T2);
  if (n == 1) {
    // Sharing vertex s: they overlap iff the edge of one opposite s meets the other.
    int a[2], b[2], ka = 0, kb = 0;
    for (int v : t1.v)
      if (v != shared[0]) a[ka++] = v;
    for (int v : t2.v)
      if (v != shared[0]) b[kb++] = v;
    return CGAL::do_intersect(K::Segment_3(p(b[0]), p(b[1])), T1) ||
           CGAL::do_intersect(K::Segment_3(p(a[0]), p(a[1])), T2);
  }
  if (n == 2) {
    // Sharing edge uv: they overlap iff coplanar and folded onto each other.
    const int u = shared[0], v = shared[1];
    const int a = opposite_vertex(t1, u, v), b = opposite_vertex(t2, u, v);
    return CGAL::orientation(p(u), p(v), p(a), p(b)) == CGAL::COPLANAR &&
           CGAL::coplanar_orientation(p(u), p(v), p(a), p(b)) == CGAL::POSITIVE;
  }
  return false;  // the same three vertices: reported as a duplicate
}

}  // namespace

std::vector<std::pair<int, int>> find_self_intersections(const Mesh& m, size_t limit, int threads) {
  using Box = CGAL::Box_intersection_d::Box_with_info_d<double, 3, int>;
  std::vector<Box> boxes;
  boxes.reserve(m.triangles.size());
  for (size_t f = 0; f < m.triangles.size(); ++f) {
    const auto& v = m.triangles[f].v;
    CGAL::Bbox_3 b = cgal(m.points[v[0]]).bbox() + cgal(m.points[v[1]]).bbox() + cgal(m.points[v[2]]).bbox();
    boxes.emplace_back(b, static_cast<int>(f));
  }
  // Two halves at the median box centre along x, each searched on its own
  // (on two threads when there are), then the pairs across the cut: only
  // boxes that reach into the other half's x-range can make one. The same
  // three searches on any number of threads, so the same pairs. Validation
  // was the largest phase of a surface-only run (elephant: 0.27 -> 0.19 s).
  std::vector<Box> left, right, left_reach, right_reach;
  if (boxes.size() >= 4096) {
    auto centre = [](const Box& b) { return b.min_coord(0) + b.max_coord(0); };
    const auto middle = boxes.begin() + static_cast<long>(boxes.size() / 2);
    std::nth_element(boxes.begin(), middle, boxes.end(), [&](const Box& a, const Box& b) {
      return centre(a) < centre(b) || (centre(a) == centre(b) && a.info() < b.info());
    });
    left.assign(boxes.begin(), middle);
    right.assign(middle, boxes.end());
    double right_lo = std::numeric_limits<double>::infinity(), left_hi = -right_lo;
    for (const Box& b : right) right_lo = std::min(right_lo, b.min_coord(0));
    for (const Box& b : left) left_hi = std::max(left_hi, b.max_coord(0));
    for (const Box& b : left)
      if (b.max_coord(0) >= right_lo) left_reach.push_back(b);
    for (const Box& b : right)
      if (b.min_coord(0) <= left_hi) right_reach.push_back(b);
    std::vector<Box>().swap(boxes);
  } else {
    left = std::move(boxes);
  }
  // Each search lets its boxes go when it is done (CGAL copies a self
  // search's boxes again): beside the pipeline the three run one after the
  // other while the tetrahedralization grows, and holding them all to the
  // end raised a 1.3M-facet surface's peak by 130 MB.
  auto release = [](std::vector<Box>& v) { std::vector<Box>().swap(v); };
  std::vector<std::pair<int, int>> found[3];
  for_each_chunk(3, 1, [&](long task, long, long) {
    auto& out = found[task];
    auto report = [&](const Box& a, const Box& b) {
      if (facets_intersect(m, m.triangles[a.info()], m.triangles[b.info()])) {
        out.emplace_back(std::min(a.info(), b.info()), std::max(a.info(), b.info()));
        if (out.size() >= limit) throw out.size();
      }
    };
    try {
      if (task == 0) CGAL::box_self_intersection_d(left.begin(), left.end(), report);
      if (task == 1) CGAL::box_self_intersection_d(right.begin(), right.end(), report);
      if (task == 2)
        CGAL::box_intersection_d(left_reach.begin(), left_reach.end(), right_reach.begin(), right_reach.end(), report);
    } catch (size_t) {
      // enough examples collected
    }
    if (task == 0) release(left);
    if (task == 1) release(right);
    if (task == 2) release(left_reach), release(right_reach);
  }, threads);
  std::vector<std::pair<int, int>> all;
  for (const auto& part : found) all.insert(all.end(), part.begin(), part.end());
  std::sort(all.begin(), all.end());
  if (all.size() > limit) all.resize(limit);
  return all;
}

void throw_self_intersections(const std::vector<std::pair<int, int>>& crossings) {
  if (crossings.empty()) return;
  std::ostringstream s;
  s << "the surface intersects itself: facet pairs";
  for (size_t i = 0; i < crossings.size() && i < 10; ++i)
    s << (i ? ", " : " ") << "(" << crossings[i].first << ", " << crossings[i].second << ")";
  if (crossings.size() >= 10) s << ", ...";
  throw SelfIntersectionError(s.str(), crossings);
}

SurfaceCheck validate_surface(const Mesh& surface, const EdgeMap* given, bool self_intersections) {
  SurfaceCheck out;
  check_indices_and_coordinates(surface);
  check_degenerate(surface);
  check_duplicates(surface);
  std::optional<EdgeMap> own;
  const EdgeMap& edges = given ? *given : own.emplace(surface.triangles);
  check_orientation(surface, edges, out);
  if (self_intersections) throw_self_intersections(find_self_intersections(surface));
  return out;
}

}  // namespace vd
