#include "volume/cap_vertices.h"

#include <algorithm>
#include <cmath>
#include <unordered_set>

#include "geometry/predicates.h"
#include "mesh/tet_faces.h"
#include "quality/tet_quality.h"
#include "surface/delaunayzation.h"
#include "surface/edge_map.h"
#include "surface/face_patches.h"
#include "surface/surface_geometry.h"
#include "surface/volume_keeper.h"

namespace vd {
namespace {

// Under this angle a tetrahedron of four surface vertices with no face on
// the surface, two of them on opposite sides of a wall, gets its centroid.
// Only the nearly degenerate ones (the casting's were at 0.01 deg): at 3 deg,
// before the wall conditions of spans_a_wall, the lever got 14 % more
// tetrahedra under 10 deg (3,340 -> 3,803), at 1 deg 4 %.
constexpr double kFlatAcrossAWallDeg = 1.0;

// A fold edge that is one side of a face's corner under this angle, the
// corner's two sides on the face's border, is not split: the split makes
// the same corner half as long, with the same cap in it and the two border
// nodes across it twice as close. Where a seam of occt_MODERN_Exhaust_1.brep
// leaves a face tangentially (a 0.7 deg corner), three rounds put them
// 0.00027 apart next to tetrahedra 0.2 long: 0.04 deg. CAD corpus,
// 2026-11-27, against every fold split: the Exhaust 0.04 -> 0.24 deg (299 ->
// 199 tetrahedra under 10 deg), caxif_as1-oc-214.stp 1.16 -> 4.14 (50 ->
// 8), the fusee 3.91 -> 4.90 (24 -> 13), the U-joint 273 -> 241 under 10,
// gmsh_part.step 7.38 -> 7.26 deg (18 -> 9), the rest within 11 tetrahedra
// under 10 deg. At 5 deg the Exhaust kept 0.20 deg; at 20 the fusee fell to
// 2.53.
constexpr double kSharpFaceCornerDeg = 10.0;

// Is the surface edge {a, b} a side of a face's corner under
// kSharpFaceCornerDeg, the corner's two sides on the face's border?
// `facets_on(x, y)`: the surface facets on edge {x, y}.
template <class FacetsOn>
bool side_of_sharp_border_corner(const Mesh& m, int a, int b, const FacetsOn& facets_on) {
  const auto border = [&](const std::vector<int>& on) {
    return on.size() != 2 || m.triangles[on[0]].face != m.triangles[on[1]].face;
  };
  const auto on_border = [&](int x, int y) { return border(facets_on(x, y)); };
  const std::vector<int> sides = facets_on(a, b);
  if (!border(sides)) return false;
  const double sharp = kSharpFaceCornerDeg * M_PI / 180.0;
  for (const int f : sides) {
    const int c = opposite_vertex(m.triangles[f], a, b);
    if ((corner_angle(m.points[a], m.points[b], m.points[c]) < sharp && on_border(a, c)) ||
        (corner_angle(m.points[b], m.points[a], m.points[c]) < sharp && on_border(b, c)))
      return true;
  }
  return false;
}

// On CAD input, a cap point whose new tetrahedra would have an angle under
// this, and no larger than the cap's, is refused when the cap's fold lies
// inside a face (insert_cap_vertices): the fold is split instead, on the
// face. The capacitor's caps on its leads' cylinders
// (kicad_CP_Radial_D10.0mm.step at 1.5 and 2 times its size; caps of 0.018
// and 0.029 deg, points making 0.006 and 0.010 deg): 0.020 -> 7.52 deg and
// 0.12 -> 8.76 deg. The bound: at 1 deg, the caps of a lone ellipsoid
// (tests/cli/test_cad.py; caps of 0.02 to 0.5 deg, points making 0.008 to
// 0.17 deg) had their folds split too, 5.75 -> 2.81 deg, where the points
// had let the sliver pass reach 5.75. On every fold, refusing every point no
// fairer than its cap, the splits made flatter tetrahedra than the points
// did (gmsh_917_fusee.stp 4.90 -> 1.01 deg, gmsh_part.step 7.25 -> 3.30);
// with the bound of 1 deg, but on the borders between faces too, the
// U-joint's caps over its tangent borders stayed or came back (0.34 ->
// 0.0068 deg).
constexpr double kFairCapPointDeg = 0.01;

struct Cap {
  int tet;
  Vec3 point;
  double fold_length;
  std::array<int, 2> fold{-1, -1};
  std::vector<Vec3> fallbacks;
  double angle_deg = 0;
  bool fold_inside_a_face = false;
};

}  // namespace

std::vector<CapPoint> cap_breaking_points(const Mesh& m, const DelaunayTetrahedralization& dt,
                                          double sliver_angle_deg, double ridge_angle_deg, double clearance) {
  const std::vector<char> on_surface = surface_vertex_flags(m.points.size(), m.triangles);
  const TripleIndex facet_of(m.triangles, [](const Triangle& t) { return t.v; });
  const double cos_ridge = std::cos(ridge_angle_deg * M_PI / 180.0);
  const double cos_sliver = std::cos(sliver_angle_deg * M_PI / 180.0);
  std::vector<std::vector<int>> facets_at;  // filled when first asked
  auto facets_at_vertices = [&]() -> const std::vector<std::vector<int>>& {
    if (facets_at.empty()) {
      facets_at.resize(m.points.size());
      for (size_t f = 0; f < m.triangles.size(); ++f)
        for (int v : m.triangles[f].v) facets_at[v].push_back(static_cast<int>(f));
    }
    return facets_at;
  };
  auto longest_edge = [&](const Tetrahedron& t) {
    double longest = 0;
    for (int i = 0; i < 4; ++i)
      for (int j = i + 1; j < 4; ++j) longest = std::max(longest, norm(m.points[t.v[i]] - m.points[t.v[j]]));
    return longest;
  };
  // Two of t's vertices on opposite sides of a wall: their normals into t's
  // region (sums over their facets) more than 120 deg apart. Not on a
  // surface inside one region, which has no inside, and not at a sharp
  // feature (a vertex whose facets fold sharply, or a facet with a corner
  // under 10 deg) and not across a wall thinner than a quarter of the
  // tetrahedron's longest edge: a spike or a wedge of the input is thin by
  // design, and a point inside it only cuts its small angle (the 1 deg wedge
  // of plc-sharp: 0.82 -> 0.50 deg, the pump's smallest angle 1.12 -> 0.24).
  auto spans_a_wall = [&](const Tetrahedron& t) {
    facets_at_vertices();
    Vec3 normal[4];
    for (int i = 0; i < 4; ++i) {
      Vec3 sum{0, 0, 0};
      for (int f : facets_at[t.v[i]]) {
        const Triangle& tri = m.triangles[f];
        if (tri.front == tri.back) return false;
        const Vec3 nf = facet_normal(m.points, tri);
        if (tri.front == t.region) sum = sum + nf;
        else if (tri.back == t.region) sum = sum - nf;
        if (smallest_corner_angle(m.points, tri) < 10.0 * M_PI / 180.0) return false;
      }
      if (!(norm(sum) > 0.7 * static_cast<double>(facets_at[t.v[i]].size()))) return false;
      normal[i] = sum;
    }
    const double longest = longest_edge(t);
    for (int i = 0; i < 4; ++i)
      for (int j = i + 1; j < 4; ++j) {
        if (!(dot(normal[i], normal[j]) < -0.5 * norm(normal[i]) * norm(normal[j]))) continue;
        // As thick as the tetrahedron is wide: in a wall much thinner than
        // its facets (the wedge away from its edge) no point makes fair
        // tetrahedra.
        const Vec3 across = normalized(normalized(normal[i]) - normalized(normal[j]));
        if (std::abs(dot(m.points[t.v[j]] - m.points[t.v[i]], across)) > 0.25 * longest) return true;
      }
    return false;
  };
  // Or its centroid far from the planes of the facets at its vertices (at
  // least 0.15 of its longest edge; the plane of a facet is never farther than
  // the facet): a flat tetrahedron across a groove or a slot, whose corner
  // vertices' normals are no wall's (the Block's 0.8-high grooves, flat
  // rectangles of 2.08 x 0.8 at 0.0004 deg). A spike's or a wedge's thin
  // tip keeps its centroid close to a facet plane.
  auto thick_at_centroid = [&](const Tetrahedron& t, const Vec3& centroid) {
    facets_at_vertices();
    const double longest = longest_edge(t);
    for (int i = 0; i < 4; ++i)
      for (int f : facets_at[t.v[i]]) {
        const Triangle& tri = m.triangles[f];
        if (tri.front == tri.back) return false;
        const Vec3 nf = normalized(facet_normal(m.points, tri));
        if (std::abs(dot(centroid - m.points[tri.v[0]], nf)) < 0.15 * longest) return false;
      }
    return true;
  };
  const auto facets_on = [&](int x, int y) {
    std::vector<int> on;
    for (const int f : facets_at_vertices()[x])
      if (std::find(m.triangles[f].v.begin(), m.triangles[f].v.end(), y) != m.triangles[f].v.end()) on.push_back(f);
    return on;
  };
  std::vector<Cap> caps;
  std::unordered_set<long long> folds;
  for (size_t ti = 0; ti < m.tets.size(); ++ti) {
    const Tetrahedron& t = m.tets[ti];
    if (!(on_surface[t.v[0]] && on_surface[t.v[1]] && on_surface[t.v[2]] && on_surface[t.v[3]])) continue;
    const Vec3 &p0 = m.points[t.v[0]], &p1 = m.points[t.v[1]], &p2 = m.points[t.v[2]], &p3 = m.points[t.v[3]];
    const double angle = smallest_dihedral_deg(p0, p1, p2, p3);
    if (angle >= sliver_angle_deg) continue;
    int faces[4], n = 0;
    for (int i = 0; i < 4; ++i)
      if (facet_of.find(face_opposite(t.v, i)) >= 0) faces[n++] = i;
    // Flat across a thin wall: four surface vertices, two on each side, in
    // one plane (rows of an extruded tessellation), no face on the surface.
    // The random shift moves them only along the surface, so nothing opens
    // it, and the sliver pass cannot move a vertex off its face. Its
    // centroid, inside the wall, does (meshlab_casting.off 0.01 -> 4.58 deg).
    const Vec3 centroid = 0.25 * (p0 + p1 + p2 + p3);
    if (n == 0 && angle < kFlatAcrossAWallDeg && orientation(p0, p1, p2, p3) != 0 &&
        (spans_a_wall(t) || thick_at_centroid(t, centroid))) {
      double shortest = 1e300;
      for (int x = 0; x < 4; ++x)
        for (int y = x + 1; y < 4; ++y) shortest = std::min(shortest, norm(m.points[t.v[x]] - m.points[t.v[y]]));
      // Refused (it would take a facet: a wall or a groove thinner than
      // the facets' circumspheres), the longest of its edges on the surface
      // is split as a fold's would be, and the cospherical rows of the two
      // sides no longer meet in one plane.
      std::array<int, 2> edge{-1, -1};
      double edge_length = 0;
      for (int x = 0; x < 4; ++x)
        for (int y = x + 1; y < 4; ++y) {
          const int a = t.v[x], b = t.v[y];
          const double length = norm(m.points[a] - m.points[b]);
          if (length <= edge_length || facets_on(a, b).empty()) continue;
          edge = {a, b};
          edge_length = length;
        }
      caps.push_back({static_cast<int>(ti), centroid, 2 * shortest, edge, {}, angle, false});
      continue;
    }
    if (n != 2) continue;
    // The facets' normals into the cap's region.
    Vec3 inward{0, 0, 0};
    Vec3 normal[2];
    int face[2];
    bool sided = true;
    for (int k = 0; k < 2; ++k) {
      const Triangle& f = m.triangles[facet_of.find(face_opposite(t.v, faces[k]))];
      face[k] = f.face;
      const Vec3 nf = facet_normal(m.points, f);
      // The side the cap's fourth vertex is on, not the region's: on a
      // surface inside a region (both sides the same) the cap may be on
      // either (a horizon in cgal_horizons_in_domain: 0.93 deg).
      const int side = orientation(m.points[f.v[0]], m.points[f.v[1]], m.points[f.v[2]], m.points[t.v[faces[k]]]);
      sided = sided && side != 0 && (f.front == t.region || f.back == t.region);
      normal[k] = side > 0 ? nf : -1.0 * nf;
      inward = inward + normal[k];
    }
    if (!sided || dot(normal[0], normal[1]) >= cos_ridge) continue;  // flat enough for case A
    // The two facets meeting at the fold edge at under the sliver angle
    // inside the tetrahedron (normals into it nearly opposite): it is the tip
    // of the input's own wedge, whose angle no point can raise, and a point
    // inside would only split it (a 1 deg wedge: 1.00 -> 0.50 deg).
    if (dot(normal[0], normal[1]) < -cos_sliver) continue;
    // The fold edge: the two vertices both facets share.
    int a = -1, b = -1;
    for (int i = 0; i < 4; ++i)
      if (i != faces[0] && i != faces[1]) (a < 0 ? a : b) = t.v[i];
    if (!folds.insert((static_cast<long long>(std::min(a, b)) << 32) | std::max(a, b)).second) continue;
    const double length = norm(m.points[b] - m.points[a]);
    const bool inside_a_face = face[0] == face[1];
    if (!(norm(inward) > 0) || !(length > 0)) continue;
    if (orientation(p0, p1, p2, p3) == 0) continue;
    // Deep enough to make fair tetrahedra with the two facets, but inside
    // the cap's circumsphere: from the fold's middle, else from the cap's
    // centroid (inside its circumsphere, as the whole tetrahedron is), ever
    // shallower.
    const Vec3 middle = 0.5 * (m.points[a] + m.points[b]);
    const Vec3 in = normalized(inward);
    for (double depth : {0.35, 0.2, 0.1, 0.05, 0.02, 0.01, 0.005}) {
      const Vec3 from_middle = middle + (depth * length) * in, from_centroid = centroid + (depth * length) * in;
      const Vec3* p = side_of_circumsphere(p0, p1, p2, p3, from_middle) == SphereSide::inside ? &from_middle
                      : side_of_circumsphere(p0, p1, p2, p3, from_centroid) == SphereSide::inside ? &from_centroid
                                                                                                 : nullptr;
      if (!p) continue;
      caps.push_back({static_cast<int>(ti), *p, length, {a, b}, {}, angle, inside_a_face});
      break;
    }
    // A fold on a side of a sharp border corner is not split when its
    // point is refused (split_cap_folds), and that point, under the fold's
    // middle, mostly is: it lies in the circumspheres of the tetrahedra
    // over the corner's thin facet. Points under the middles of the cap's
    // other surface edges are offered too; the one whose new tetrahedra are
    // fairest goes in (insert_cap_vertices). caxif_as1-oc-214.stp's pins
    // stand tangent to its block's edges, in corners of 3.2 deg: 4.14 ->
    // 8.79 deg at seeds 1 and 3 (2026-11-27).
    if (!caps.empty() && caps.back().tet == static_cast<int>(ti) && side_of_sharp_border_corner(m, a, b, facets_on)) {
      for (const double depth : {0.2, 0.1, 0.05})
        for (int k = 0; k < 2; ++k) {
          const int c = t.v[faces[1 - k]];  // facet k's vertex off the fold
          for (const int e : {a, b}) {
            const Vec3 q = 0.5 * (m.points[e] + m.points[c]) + (depth * length) * in;
            if (side_of_circumsphere(p0, p1, p2, p3, q) == SphereSide::inside) caps.back().fallbacks.push_back(q);
          }
        }
    }
    // Else the centroid itself, inside the cap: when the circumsphere's
    // centre lies outside the region, the ball may reach inward less than
    // the shallowest depth above. The cylinder head's flattest caps were
    // such (smallest angle 0.12 -> 0.76 deg).
    if ((caps.empty() || caps.back().tet != static_cast<int>(ti)) &&
        side_of_circumsphere(p0, p1, p2, p3, centroid) == SphereSide::inside)
      caps.push_back({static_cast<int>(ti), centroid, length, {a, b}, {}, angle, inside_a_face});
  }
  if (caps.empty()) return {};

  std::vector<CapPoint> out;
  const auto fits = [&](const Cap& c, const Vec3& p) {
    if (dt.label_at(p) != m.tets[c.tet].region) return false;
    const std::array<int, 4> cell = dt.locate(p);
    bool clear = true;
    for (int v : cell) clear = clear && norm(m.points[v] - p) > clearance * c.fold_length;
    for (const CapPoint& q : out) clear = clear && norm(q.point - p) > 0.1 * c.fold_length;
    return clear;
  };
  for (const Cap& c : caps) {
    if (!fits(c, c.point)) continue;
    CapPoint point{c.point, {}, c.fold, c.angle_deg, c.fold_inside_a_face};
    for (const Vec3& f : c.fallbacks)
      if (fits(c, f)) point.fallbacks.push_back(f);
    out.push_back(std::move(point));
  }
  return out;
}

int insert_cap_vertices(Mesh& m, DelaunayTetrahedralization& dt, const std::vector<CapPoint>& points,
                        std::vector<std::array<int, 2>>* refused_folds, long* from_fallbacks, bool refuse_unfair) {
  const TripleIndex surface(m.triangles, [](const Triangle& t) { return t.v; });
  // Room for all at once: a handful of points doubling the vertex list beside
  // the tetrahedralization was 1.1 MB of a 125k-tetrahedra box's peak.
  m.points.reserve(m.points.size() + points.size());
  if (!m.point_size.empty()) m.point_size.reserve(m.points.size() + points.size());
  int kept = 0;
  std::vector<std::array<int, 3>> taken;
  for (const CapPoint& cap : points) {
    // Asked before inserting: a point inserted and taken out again left
    // CGAL's cells in an order that depended on memory addresses, so the
    // same run wrote its tetrahedra in another order each time.
    const auto keeps_facets = [&](const Vec3& q, std::vector<std::array<int, 3>>* around) {
      bool keeps = dt.faces_taken_by(q, taken, around);
      for (const auto& f : taken) keeps = keeps && surface.find(f) < 0;
      return keeps;
    };
    // The smallest angle of the tetrahedra q would make with the faces around
    // its conflict zone.
    std::vector<std::array<int, 3>> around;
    const auto fairness = [&](const Vec3& q) {
      double smallest = 180;
      for (const auto& f : around)
        smallest = f[0] < 0 || f[1] < 0 || f[2] < 0
                       ? 0
                       : std::min(smallest, smallest_dihedral_deg(m.points[f[0]], m.points[f[1]], m.points[f[2]], q));
      return smallest;
    };
    // Over a fold inside a face, a point whose tetrahedra would be nearly
    // flat and no fairer than the cap is refused, as one that takes a facet
    // is (kFairCapPointDeg).
    Vec3 p = cap.point;
    const bool judged = refuse_unfair && cap.fold_inside_a_face;  // the faces around only then
    bool keeps = keeps_facets(p, judged ? &around : nullptr);
    if (keeps && judged) {
      const double fair = fairness(p);
      keeps = fair > cap.cap_angle_deg || fair >= kFairCapPointDeg;
    }
    if (!keeps) {
      // The fallback whose new tetrahedra are the fairest.
      double best = 0;
      for (const Vec3& q : cap.fallbacks) {
        if (!keeps_facets(q, &around)) continue;
        const double smallest = fairness(q);
        if (smallest > best) best = smallest, p = q, keeps = true;
      }
      if (keeps && from_fallbacks) ++*from_fallbacks;
    }
    if (!keeps) {
      if (refused_folds && cap.fold[0] >= 0) refused_folds->push_back(cap.fold);
      continue;
    }
    // Its conflict zone crosses no facet: one region, whose label the new
    // tetrahedra take.
    const int region = dt.label_at(p);
    dt.insert_one(p, static_cast<int>(m.points.size()));
    dt.label_star(static_cast<int>(m.points.size()), region);
    m.points.push_back(p);
    if (!m.point_size.empty()) m.point_size.push_back(0.0);
    ++kept;
  }
  return kept;
}

int split_cap_folds(Mesh& m, const std::vector<std::array<int, 2>>& folds, const SurfaceGeometry* geometry,
                    long* left_at_sharp_corners, double volume_limit) {
  VolumeKeeper volume;
  if (geometry && volume_limit > 0) volume = VolumeKeeper(m, geometry->region_volumes(), volume_limit);
  std::vector<std::uint64_t> keys;
  for (const auto& [a, b] : folds) keys.push_back(edge_key(a, b));
  std::sort(keys.begin(), keys.end());
  keys.erase(std::unique(keys.begin(), keys.end()), keys.end());
  // Each fold once, and none in a facet an earlier split of this call
  // changed: its edge may be gone.
  const EdgeFacetPairs adjacency(m.triangles);
  // Faces are only split here, never flipped, so the adjacency's faces
  // across an edge stay true through the splits of this call.
  const auto facets_on = [&](int x, int y) { return adjacency.facets(edge_key(x, y)); };
  std::vector<char> touched(m.triangles.size(), 0);
  int split = 0;
  for (std::uint64_t key : keys) {
    const std::vector<int> sharing = adjacency.facets(key);
    bool clear = !sharing.empty();
    for (int f : sharing) clear = clear && !touched[f];
    if (!clear) continue;
    const int a = static_cast<int>(key >> 32), b = static_cast<int>(key & 0xffffffffu);
    const bool at_sharp_corner = side_of_sharp_border_corner(m, a, b, facets_on);
    if (at_sharp_corner) {
      if (left_at_sharp_corners) ++*left_at_sharp_corners;
      continue;
    }
    const int n = static_cast<int>(m.points.size());
    const Vec3 middle = 0.5 * (m.points[a] + m.points[b]);
    Vec3 point = geometry ? place_split_point(m, *geometry, a, b, sharing, middle) : middle;
    if (!volume.take_split(m, a, b, sharing, point)) point = middle;
    m.points.push_back(point);
    if (!m.point_size.empty()) m.point_size.push_back(0.5 * (m.point_size[a] + m.point_size[b]));
    for (int f : sharing) {
      touched[f] = 1;
      Triangle& t = m.triangles[f];
      int k = 0;
      while (!((t.v[k] == a && t.v[(k + 1) % 3] == b) || (t.v[k] == b && t.v[(k + 1) % 3] == a))) ++k;
      Triangle second = t;
      const int p = t.v[k], q = t.v[(k + 1) % 3], r = t.v[(k + 2) % 3];
      t.v = {p, n, r};
      second.v = {n, q, r};
      m.triangles.push_back(second);
    }
    ++split;
  }
  return split;
}

}  // namespace vd
