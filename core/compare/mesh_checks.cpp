#include "compare/mesh_checks.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <sstream>

#include "geometry/triangle_index.h"
#include "volume/region_tetrahedra.h"

namespace vd::compare {
namespace {

double longest(const Vec3& a, const Vec3& b, const Vec3& c) {
  return std::max({norm(b - a), norm(c - b), norm(a - c)});
}

Vec3 centroid(const Vec3& a, const Vec3& b, const Vec3& c) { return (1.0 / 3.0) * (a + b + c); }

std::array<Vec3, 3> corners(const std::vector<Vec3>& p, const std::array<int, 3>& v) {
  return {p[static_cast<size_t>(v[0])], p[static_cast<size_t>(v[1])], p[static_cast<size_t>(v[2])]};
}

// One side of a boundary face: the region of the tetrahedron there, and the
// face's vertices ordered so that the normal points out of that tetrahedron.
struct BoundaryEntry {
  std::array<int, 3> v;
  int region;
  int face;  // index among the distinct boundary faces
};

// The face of tetrahedron v opposite its vertex i, and a triangle's vertex
// ids in increasing order (a key whatever the orientation).
std::array<int, 3> face_opposite(const std::array<int, 4>& v, int i) {
  std::array<int, 3> f{};
  for (int j = 0, c = 0; j < 4; ++j)
    if (j != i) f[static_cast<size_t>(c++)] = v[static_cast<size_t>(j)];
  return f;
}

std::array<int, 3> sorted_triple(std::array<int, 3> k) {
  std::sort(k.begin(), k.end());
  return k;
}

struct FaceRecord {
  std::array<int, 3> key;
  int tet;
  int apex;
  bool operator<(const FaceRecord& o) const { return key < o.key; }
};

void add_unique(std::vector<int>& set, int x) {
  if (std::find(set.begin(), set.end(), x) == set.end()) set.push_back(x);
}

}  // namespace

InputSurface::InputSurface(const Mesh& input) : mesh_(input) {
  const auto& p = mesh_.points;
  Vec3 lo{std::numeric_limits<double>::max(), std::numeric_limits<double>::max(), std::numeric_limits<double>::max()};
  Vec3 hi = -1.0 * lo;
  std::vector<char> used(p.size(), 0);
  for (const Triangle& t : mesh_.triangles)
    for (int v : t.v) used[static_cast<size_t>(v)] = 1;
  for (size_t i = 0; i < p.size(); ++i) {
    if (!used[i]) continue;
    ++surface_vertices_;
    for (int k = 0; k < 3; ++k) {
      lo[k] = std::min(lo[k], p[i][k]);
      hi[k] = std::max(hi[k], p[i][k]);
    }
  }
  if (surface_vertices_ > 0) {
    diagonal_ = norm(hi - lo);
    centre_ = 0.5 * (lo + hi);
  }
  std::vector<std::array<Vec3, 3>> tris;
  tris.reserve(mesh_.triangles.size());
  normals_.reserve(mesh_.triangles.size());
  longest_edge_.reserve(mesh_.triangles.size());
  region_tags_ = !mesh_.triangles.empty();
  for (const Triangle& t : mesh_.triangles) {
    const auto c = corners(p, t.v);
    tris.push_back(c);
    normals_.push_back(normalized(cross(c[1] - c[0], c[2] - c[0])));
    longest_edge_.push_back(longest(c[0], c[1], c[2]));
    if (t.front < 0 || t.back < 0) region_tags_ = false;
  }
  index_ = std::make_unique<TriangleIndex>(tris);
}

InputSurface::~InputSurface() = default;

std::vector<std::string> MeshChecks::problems(double volume_tolerance) const {
  std::vector<std::string> out;
  auto say = [&](long n, const char* what) {
    if (n > 0) out.push_back(std::to_string(n) + " " + what);
  };
  if (tets == 0) out.push_back("no tetrahedra");
  say(inverted, "inverted tetrahedra");
  say(non_manifold_faces, "faces shared by more than two tetrahedra");
  say(boundary_faces_off_input, "boundary faces off the input surface");
  say(input_facets_uncovered, "input facets not covered by the boundary");
  say(boundary_faces_untagged, "boundary faces without a face id");
  say(face_ids_wrong, "boundary faces with a wrong face id");
  say(facet_sides_wrong, "input facets with other regions on their sides than tagged");
  say(facet_sides_ambiguous, "input facets with two regions on one side");
  if (tets > 0 && !volumes_ok(volume_tolerance)) {
    std::ostringstream s;
    s << "region volumes differ from the input's by up to " << max_relative_volume_error << " (relative)";
    out.push_back(s.str());
  }
  return out;
}

MeshChecks check_mesh(const InputSurface& input, const Mesh& result) {
  MeshChecks c;
  const auto& P = result.points;
  const Mesh& in = input.mesh();
  const double k = kConformityTolerance;

  // Tetrahedra: validity, volumes per region, quality.
  std::vector<char> used(P.size(), 0);
  std::vector<FaceRecord> faces;
  faces.reserve(result.tets.size() * 4);
  std::map<int, RegionVolume> regions;
  for (size_t t = 0; t < result.tets.size(); ++t) {
    const auto& v = result.tets[t].v;
    for (int x : v) used[static_cast<size_t>(x)] = 1;
    const double vol = tet_volume(P[v[0]], P[v[1]], P[v[2]], P[v[3]]);
    if (vol <= 0) ++c.inverted;
    RegionVolume& r = regions[result.tets[t].region];
    r.region = result.tets[t].region;
    ++r.tets;
    r.volume += vol;
    for (int i = 0; i < 4; ++i) faces.push_back({sorted_triple(face_opposite(v, i)), static_cast<int>(t), v[i]});
    for (double a : dihedral_angles_deg(P[v[0]], P[v[1]], P[v[2]], P[v[3]]))
      ++c.dihedral_histogram_2deg[static_cast<size_t>(std::clamp(static_cast<int>(a / 2.0), 0, 89))];
  }
  c.tets = static_cast<long>(result.tets.size());
  c.vertices = std::count(used.begin(), used.end(), 1);
  c.quality = summarize_quality(result);

  // The output's own triangles, by vertex set: their face ids.
  std::vector<std::pair<std::array<int, 3>, int>> tagged;
  tagged.reserve(result.triangles.size());
  for (const Triangle& t : result.triangles) tagged.emplace_back(sorted_triple(t.v), t.face);
  std::sort(tagged.begin(), tagged.end());
  auto face_id_of = [&](const std::array<int, 3>& key, bool& found) {
    auto it = std::lower_bound(tagged.begin(), tagged.end(), std::make_pair(key, std::numeric_limits<int>::min()));
    found = it != tagged.end() && it->first == key;
    return found ? it->second : kNoFace;
  };

  // Boundary faces of the tetrahedra, one entry per side that has a region.
  std::sort(faces.begin(), faces.end());
  std::vector<BoundaryEntry> entries;
  std::vector<std::array<int, 3>> boundary;  // distinct boundary faces (sorted keys)
  auto outward = [&](const FaceRecord& f) {
    std::array<int, 3> v = f.key;
    const Vec3 n = cross(P[v[1]] - P[v[0]], P[v[2]] - P[v[0]]);
    if (dot(n, P[f.apex] - P[v[0]]) > 0) std::swap(v[1], v[2]);
    return v;
  };
  for (size_t i = 0; i < faces.size();) {
    size_t j = i;
    while (j < faces.size() && faces[j].key == faces[i].key) ++j;
    const size_t n = j - i;
    if (n > 2) {
      ++c.non_manifold_faces;
    } else {
      bool sheet = false;
      if (n == 2 && result.tets[faces[i].tet].region == result.tets[faces[i + 1].tet].region)
        face_id_of(faces[i].key, sheet);
      if (n == 1 || sheet || result.tets[faces[i].tet].region != result.tets[faces[i + 1].tet].region) {
        const int id = static_cast<int>(boundary.size());
        boundary.push_back(faces[i].key);
        for (size_t m = i; m < j; ++m) entries.push_back({outward(faces[m]), result.tets[faces[m].tet].region, id});
      }
    }
    i = j;
  }
  faces.clear();
  faces.shrink_to_fit();
  c.boundary_faces = static_cast<long>(boundary.size());
  std::vector<char> on_boundary(P.size(), 0);
  for (const auto& f : boundary)
    for (int v : f) on_boundary[static_cast<size_t>(v)] = 1;
  c.boundary_vertices = std::count(on_boundary.begin(), on_boundary.end(), 1);
  c.boundary_vertices_added = c.boundary_vertices - input.surface_vertices();

  // Output boundary -> input surface: distance and face id of each face.
  const double diag = input.diagonal() > 0 ? input.diagonal() : 1.0;
  std::vector<double> vertex_distance(P.size(), -1.0);
  auto distance_to_input = [&](int v) {
    double& d = vertex_distance[static_cast<size_t>(v)];
    if (d < 0) d = input.index().closest(P[v]).distance;
    return d;
  };
  std::vector<int> near;
  for (const auto& key : boundary) {
    const auto t = corners(P, key);
    const Vec3 cen = centroid(t[0], t[1], t[2]);
    const Vec3 n = normalized(cross(t[1] - t[0], t[2] - t[0]));
    const auto hit = input.index().closest(cen);
    if (hit.id < 0) {
      ++c.boundary_faces_off_input;
      continue;
    }
    const double length = std::max(longest(t[0], t[1], t[2]), input.longest_edge(hit.id));
    double d = hit.distance;
    for (int v : key) d = std::max(d, distance_to_input(v));
    c.max_distance_to_input = std::max(c.max_distance_to_input, d / diag);
    if (d > k * length) ++c.boundary_faces_off_input;
    // The input facet under the face: the nearest, and among nearly as near
    // ones the most parallel (a thin face beside a sharp edge).
    int under = hit.id;
    input.index().within(cen, hit.distance + k * length, near);
    double best = -1;
    for (int f : near) {
      const double a = std::abs(dot(n, input.normal(f)));
      if (a > best + 1e-12) best = a, under = f;
    }
    bool found = false;
    const int face = face_id_of(key, found);
    if (!found) ++c.boundary_faces_untagged;
    else if (face != in.triangles[static_cast<size_t>(under)].face) ++c.face_ids_wrong;
  }

  // Input surface -> output boundary: coverage, and the regions the mesh put
  // on both sides of each input facet.
  std::vector<std::array<Vec3, 3>> entry_triangles;
  entry_triangles.reserve(entries.size());
  for (const auto& e : entries) entry_triangles.push_back(corners(P, e.v));
  const TriangleIndex out_index(entry_triangles);
  std::vector<double> input_vertex_distance(in.points.size(), -1.0);
  auto distance_to_output = [&](int v) {
    double& d = input_vertex_distance[static_cast<size_t>(v)];
    if (d < 0) d = out_index.closest(in.points[static_cast<size_t>(v)]).distance;
    return d;
  };
  std::vector<std::array<int, 2>> sides(in.triangles.size(), {0, 0});  // front, back
  std::vector<int> front, back;
  for (size_t f = 0; f < in.triangles.size(); ++f) {
    const Triangle& tri = in.triangles[f];
    if (input.degenerate(static_cast<int>(f))) {
      ++c.degenerate_input_facets;
      continue;
    }
    const auto t = corners(in.points, tri.v);
    const Vec3 cen = centroid(t[0], t[1], t[2]);
    const auto hit = out_index.closest(cen);
    const double length = input.longest_edge(static_cast<int>(f));
    double d = hit.distance;
    for (int v : tri.v) d = std::max(d, distance_to_output(v));
    if (std::isfinite(d)) c.max_distance_to_output = std::max(c.max_distance_to_output, d / diag);
    if (!(d <= k * length)) ++c.input_facets_uncovered;
    if (hit.id < 0) continue;
    out_index.within(cen, hit.distance + 1e-9 * length, near);
    front.clear();
    back.clear();
    const Vec3 nf = input.normal(static_cast<int>(f));
    for (int e : near) {
      const auto& q = entry_triangles[static_cast<size_t>(e)];
      const Vec3 ne = cross(q[1] - q[0], q[2] - q[0]);  // out of the entry's region
      add_unique(dot(ne, nf) > 0 ? back : front, entries[static_cast<size_t>(e)].region);
    }
    if (front.size() > 1 || back.size() > 1) ++c.facet_sides_ambiguous;
    sides[f] = {front.empty() ? 0 : *std::min_element(front.begin(), front.end()),
                back.empty() ? 0 : *std::min_element(back.begin(), back.end())};
    if (input.region_tags() && (sides[f][0] != tri.front || sides[f][1] != tri.back)) ++c.facet_sides_wrong;
  }
  c.region_tags_checked = input.region_tags();

  // Volumes: the tetrahedra of each region against the volume the input
  // facets enclose for it (divergence theorem about the box centre).
  c.volume_reference = input.region_tags() ? "input facets with their region tags"
                                           : "input facets with the regions the mesh put on their sides";
  for (size_t f = 0; f < in.triangles.size(); ++f) {
    const Triangle& tri = in.triangles[f];
    const int fr = input.region_tags() ? tri.front : sides[f][0];
    const int bk = input.region_tags() ? tri.back : sides[f][1];
    if (fr == bk) continue;
    const auto t = corners(in.points, tri.v);
    const double v = tet_volume(input.centre(), t[0], t[1], t[2]);
    if (bk > 0) regions[bk].region = bk, regions[bk].reference += v;
    if (fr > 0) regions[fr].region = fr, regions[fr].reference -= v;
  }
  for (auto& [id, r] : regions) {
    if (id <= 0 && r.reference == 0) {
      if (r.tets > 0) c.regions.push_back(r);  // tetrahedra outside every region: shown, error 1
      if (r.tets > 0) c.regions.back().relative_error = 1, c.max_relative_volume_error = 1;
      continue;
    }
    const double scale = std::max(std::abs(r.reference), std::abs(r.volume));
    r.relative_error = scale > 0 ? std::abs(r.volume - r.reference) / scale : 0;
    c.max_relative_volume_error = std::max(c.max_relative_volume_error, r.relative_error);
    c.regions.push_back(r);
  }
  return c;
}

std::vector<RegionPoint> region_points(const InputSurface& input) {
  const Mesh& m = input.mesh();
  std::vector<RegionPoint> out;
  if (!input.region_tags()) return out;
  // Candidate (facet, side) pairs per region, largest inscribed circle first.
  std::map<int, std::vector<std::pair<double, int>>> candidates;  // region -> (-inradius, signed facet+1)
  for (size_t f = 0; f < m.triangles.size(); ++f) {
    if (input.degenerate(static_cast<int>(f))) continue;
    const Triangle& t = m.triangles[f];
    const auto c = corners(m.points, t.v);
    const double area = 0.5 * norm(cross(c[1] - c[0], c[2] - c[0]));
    const double perimeter = norm(c[1] - c[0]) + norm(c[2] - c[1]) + norm(c[0] - c[2]);
    const double inradius = 2 * area / perimeter;
    const int id = static_cast<int>(f) + 1;
    if (t.back > 0) candidates[t.back].emplace_back(-inradius, -id);  // behind the facet
    if (t.front > 0) candidates[t.front].emplace_back(-inradius, id);
  }
  for (auto& [region, list] : candidates) {
    std::sort(list.begin(), list.end());
    bool found = false;
    for (size_t i = 0; i < list.size() && i < 64 && !found; ++i) {
      const int f = std::abs(list[i].second) - 1;
      const double side = list[i].second > 0 ? 1.0 : -1.0;
      const auto c = corners(m.points, m.triangles[static_cast<size_t>(f)].v);
      const Vec3 cen = centroid(c[0], c[1], c[2]);
      for (double delta = 0.25 * -list[i].first; delta > 1e-6 * -list[i].first && !found; delta *= 0.25) {
        const Vec3 p = cen + (side * delta) * input.normal(f);
        // No facet nearer than the one it was put behind: the segment from
        // the facet to p crosses nothing, so p is in `region`.
        if (input.index().closest(p).distance >= delta * (1 - 1e-6)) {
          out.push_back({p, region});
          found = true;
        }
      }
    }
  }
  return out;
}

}  // namespace vd::compare
