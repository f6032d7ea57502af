#include "surface/random_shift.h"

#include <algorithm>
#include <cmath>
#include <optional>
#include <random>

#include "geometry/predicates.h"
#include "quality/tet_quality.h"
#include "surface/edge_map.h"
#include "surface/face_patches.h"

namespace vd {
namespace {

// A feature edge separates topological faces or regions, is not a plain
// manifold edge, or is a crease; vertices on it may move only along it.
// Moving a vertex of a 90-degree crease "in its tangent plane" would move
// the box's corner off the box.
bool is_feature_edge(const Mesh& m, const FacetList& on_edge, double cos_crease) {
  if (on_edge.size() != 2) return true;
  const Triangle& a = m.triangles[on_edge[0]];
  const Triangle& b = m.triangles[on_edge[1]];
  if (a.face != b.face || std::minmax(a.front, a.back) != std::minmax(b.front, b.back)) return true;
  // Same face and regions: consistently oriented, so the normals compare directly.
  return dot(facet_normal(m.points, a), facet_normal(m.points, b)) < cos_crease;
}

Vec3 random_unit(std::mt19937_64& rng) {
  std::normal_distribution<double> g(0.0, 1.0);
  for (;;) {
    const Vec3 v{g(rng), g(rng), g(rng)};
    if (norm(v) > 1e-12) return normalized(v);
  }
}

}  // namespace

ShiftStats random_shift(Mesh& m, const ShiftOptions& options, const EdgeMap* given) {
  ShiftStats stats;
  const size_t n = m.points.size();
  // The facets around each vertex in one array (counted, then filled in
  // facet order): a vector per vertex was a heap block each.
  std::vector<int> star_start(n + 1, 0), star;
  for (const Triangle& t : m.triangles)
    for (int v : t.v) ++star_start[v + 1];
  for (size_t v = 0; v < n; ++v) star_start[v + 1] += star_start[v];
  star.resize(star_start[n]);
  {
    std::vector<int> fill(star_start.begin(), star_start.end() - 1);
    for (size_t f = 0; f < m.triangles.size(); ++f)
      for (int v : m.triangles[f].v) star[fill[v]++] = static_cast<int>(f);
  }
  std::optional<EdgeMap> own;
  const EdgeMap& edges = given ? *given : own.emplace(m.triangles);
  // Local size: mean length of the incident surface edges, else the given size.
  const std::vector<double> size = surface_vertex_sizes(m, edges);

  // Feature edges, each judged once on the surface as given (judging them
  // per vertex, against neighbours already moved, was two edge look-ups
  // and two normals per facet corner: a sixth of a surface-only run). A
  // vertex keeps how many it is on and, for a vertex on a feature line, the
  // two other ends (their order does not matter: the step's sign follows
  // the drawn direction).
  struct FeatureEnds {
    int count = 0;
    int end[2] = {-1, -1};
  };
  const double cos_crease = std::cos(options.crease_angle_deg * M_PI / 180.0);
  std::vector<FeatureEnds> features(n);
  for (const auto& [key, on_edge] : edges.all()) {
    if (!is_feature_edge(m, on_edge, cos_crease)) continue;
    const auto [a, b] = edge_of_key(key);
    for (const auto& [v, w] : {std::pair{a, b}, std::pair{b, a}}) {
      FeatureEnds& f = features[v];
      if (f.count < 2) f.end[f.count] = w;
      ++f.count;
    }
  }

  std::mt19937_64 rng(options.seed);
  std::uniform_real_distribution<double> unit(0.5, 1.0);
  std::vector<Vec3> before;
  for (size_t v = 0; v < n; ++v) {
    // Draw for every vertex so that one vertex's kind does not change the
    // numbers the others get.
    const Vec3 direction = random_unit(rng);
    const double magnitude = options.relative * size[v] * unit(rng);
    const int* first = star.data() + star_start[v];
    const int* last = star.data() + star_start[v + 1];
    if (first == last) {
      if (size[v] > 0) {
        m.points[v] = m.points[v] + magnitude * direction;
        ++stats.moved_free;
      } else {
        ++stats.fixed;
      }
      continue;
    }
    const FeatureEnds& feature = features[v];
    Vec3 step;
    if (feature.count == 0) {
      Vec3 normal{0, 0, 0};
      for (const int* f = first; f != last; ++f) {
        const Triangle& t = m.triangles[*f];
        normal = normal + facet_area(m.points, t) * facet_normal(m.points, t);
      }
      const Vec3 nrm = normalized(normal);
      step = direction - dot(direction, nrm) * nrm;  // into the tangent plane
      if (norm(step) < 1e-6) {
        ++stats.fixed;
        continue;
      }
      step = magnitude * normalized(step);
    } else if (feature.count == 2) {
      const Vec3 along = normalized(m.points[feature.end[1]] - m.points[feature.end[0]]);
      step = (magnitude * (dot(direction, along) >= 0 ? 1.0 : -1.0)) * along;
    } else {
      ++stats.fixed;  // a corner
      continue;
    }
    // A coordinate the vertex shares with its whole star (a face in an axis
    // plane) or with both ends of its feature line (an edge along an axis)
    // stays exact: rounding in the normal moved vertices off such planes by
    // 1e-21 (a node meant for x = 0 at x = -1.5e-21, 14 coordinates of a
    // unit cube's mesh outside it), which breaks selecting boundary nodes
    // by their coordinates (2026-11-30).
    const Vec3 old = m.points[v];
    for (int k = 0; k < 3; ++k) {
      bool shared = true;
      if (feature.count == 2) {
        shared = m.points[feature.end[0]][k] == old[k] && m.points[feature.end[1]][k] == old[k];
      } else {
        for (const int* f = first; f != last && shared; ++f)
          for (int c : m.triangles[*f].v) shared = shared && m.points[c][k] == old[k];
      }
      if (shared) step[k] = 0;
    }
    // Refuse a move that turns an incident facet over (needles can be thinner
    // than the shift).
    before.clear();
    for (const int* f = first; f != last; ++f) before.push_back(facet_area_vector(m.points, m.triangles[*f]));
    m.points[v] = old + step;
    bool ok = true;
    for (const int* f = first; f != last && ok; ++f) {
      const Vec3& was = before[f - first];
      ok = dot(facet_area_vector(m.points, m.triangles[*f]), was) > 0.5 * dot(was, was);
    }
    if (!ok) {
      m.points[v] = old;
      ++stats.fixed;
    } else if (feature.count == 0) {
      ++stats.moved_in_plane;
    } else {
      ++stats.moved_on_edge;
    }
  }
  return stats;
}

// A tetrahedron around a vertex put back keeps this share of its smallest
// angle (or of the sliver angle, if above it). Kept whole (1.0), 12 % of
// gmsh_simple_plane.brep's shifted vertices stayed off the CAD surface
// (68,350 of 77,950 put back), whose many tetrahedra under 20 deg each
// lost a hair of their angle to any move.
constexpr double kKeptShare = 0.98;

int restore_surface_positions(Mesh& m, const std::vector<Vec3>& before, const std::vector<Vec3>& shifted,
                              double keep_above_deg) {
  const auto same = [](const Vec3& a, const Vec3& b) { return a.x == b.x && a.y == b.y && a.z == b.z; };
  const size_t n = std::min({before.size(), shifted.size(), m.points.size()});
  std::vector<char> wanted(n, 0);
  for (const Triangle& t : m.triangles)
    for (int v : t.v)
      if (static_cast<size_t>(v) < n && same(m.points[v], shifted[v]) && !same(before[v], shifted[v])) wanted[v] = 1;
  // The tetrahedra around each wanted vertex, as offsets into one array.
  std::vector<int> start(n + 1, 0);
  for (const Tetrahedron& t : m.tets)
    for (int v : t.v)
      if (static_cast<size_t>(v) < n && wanted[v]) ++start[v + 1];
  for (size_t v = 0; v < n; ++v) start[v + 1] += start[v];
  std::vector<int> around(start[n]);
  std::vector<int> fill(start.begin(), start.end() - 1);
  for (size_t t = 0; t < m.tets.size(); ++t)
    for (int v : m.tets[t].v)
      if (static_cast<size_t>(v) < n && wanted[v]) around[fill[v]++] = static_cast<int>(t);
  const auto smallest_angle = [&m](int t) {
    const auto& c = m.tets[t].v;
    return smallest_dihedral_deg(m.points[c[0]], m.points[c[1]], m.points[c[2]], m.points[c[3]]);
  };
  int restored = 0;
  std::vector<double> floor;
  for (size_t v = 0; v < n; ++v) {
    if (!wanted[v]) continue;
    floor.clear();
    for (int k = start[v]; k < start[v + 1]; ++k)
      floor.push_back(kKeptShare * std::min(smallest_angle(around[k]), keep_above_deg));
    m.points[v] = before[v];
    bool kept = true;
    for (int k = start[v]; k < start[v + 1] && kept; ++k) {
      const auto& c = m.tets[around[k]].v;
      // Positive exactly and in floating point: the sanitized CI's gmsh_Block.stp without
      // interior vertices or the sliver pass had tetrahedra flat enough for the quality
      // summary to count inverted (2026-11-30).
      kept = orientation(m.points[c[0]], m.points[c[1]], m.points[c[2]], m.points[c[3]]) > 0 &&
             positive_as_summarized(m.points[c[0]], m.points[c[1]], m.points[c[2]], m.points[c[3]]) &&
             smallest_angle(around[k]) >= floor[k - start[v]];
    }
    if (kept) ++restored;
    else m.points[v] = shifted[v];
  }
  return restored;
}

}  // namespace vd
