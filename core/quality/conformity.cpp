#include "quality/conformity.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <sstream>

#include "geometry/predicates.h"
#include "mesh/tet_faces.h"
#include "volume/region_tetrahedra.h"

namespace vd {

ConformityReport check_conformity(const Mesh& m) {
  ConformityReport r;
  // Every face of every tetrahedron, with the tetrahedra on it.
  struct Side {
    int tet;
    int apex;  // the tetrahedron's vertex off the face
  };
  std::map<std::array<int, 3>, std::vector<Side>> faces;
  for (size_t t = 0; t < m.tets.size(); ++t) {
    const auto& v = m.tets[t].v;
    if (tet_volume(m.points[v[0]], m.points[v[1]], m.points[v[2]], m.points[v[3]]) <= 0) ++r.inverted;
    for (int i = 0; i < 4; ++i) faces[sorted_triple(face_opposite(v, i))].push_back({static_cast<int>(t), v[i]});
  }
  std::map<std::array<int, 3>, int> facet_of;
  for (size_t f = 0; f < m.triangles.size(); ++f) {
    facet_of[sorted_triple(m.triangles[f].v)] = static_cast<int>(f);
  }
  for (const auto& [k, sides] : faces) {
    if (sides.size() > 2) ++r.non_manifold_faces;
    const bool boundary = sides.size() == 1 || m.tets[sides[0].tet].region != m.tets[sides[1].tet].region;
    if (boundary && !facet_of.count(k)) ++r.faces_not_on_surface;
  }
  for (const Triangle& t : m.triangles) {
    auto it = faces.find(sorted_triple(t.v));
    int front_region = 0, back_region = 0;
    if (it != faces.end())
      for (const Side& s : it->second) {
        const Vec3 &a = m.points[t.v[0]], &b = m.points[t.v[1]], &c = m.points[t.v[2]];
        const bool front = tet_volume(a, b, c, m.points[s.apex]) > 0;
        (front ? front_region : back_region) = m.tets[s.tet].region;
      }
    if (it == faces.end() && (t.front > 0 || t.back > 0)) ++r.facets_not_on_tets;
    else if (front_region != std::max(t.front, 0) || back_region != std::max(t.back, 0)) ++r.wrong_side_regions;
  }
  r.region_volume = region_volumes(m);
  r.enclosed_volume = enclosed_volumes(m);
  const size_t n = std::max(r.region_volume.size(), r.enclosed_volume.size());
  r.region_volume.resize(n, 0.0);
  r.enclosed_volume.resize(n, 0.0);
  for (size_t i = 1; i < n; ++i) {
    const double ref = std::max(std::abs(r.enclosed_volume[i]), 1e-300);
    if (r.region_volume[i] == 0 && r.enclosed_volume[i] == 0) continue;
    r.max_relative_volume_error =
        std::max(r.max_relative_volume_error, std::abs(r.region_volume[i] - r.enclosed_volume[i]) / ref);
  }
  return r;
}

namespace {
bool turned(const Mesh& m, const Tetrahedron& t) {
  return orientation(m.points[static_cast<size_t>(t.v[0])], m.points[static_cast<size_t>(t.v[1])],
                     m.points[static_cast<size_t>(t.v[2])], m.points[static_cast<size_t>(t.v[3])]) < 0;
}
}  // namespace

long count_turned_tetrahedra(const Mesh& mesh) {
  return static_cast<long>(
      std::count_if(mesh.tets.begin(), mesh.tets.end(), [&mesh](const Tetrahedron& t) { return turned(mesh, t); }));
}

long turn_inverted_tetrahedra(Mesh& mesh) {
  const bool mids = mesh.tet_mid.size() == mesh.tets.size();
  long count = 0;
  for (size_t i = 0; i < mesh.tets.size(); ++i) {
    Tetrahedron& t = mesh.tets[i];
    if (!turned(mesh, t)) continue;
    std::swap(t.v[1], t.v[2]);
    if (mids) {
      // Edges (01, 12, 20, 03, 13, 23) of (0, 2, 1, 3) are the old 20, 12,
      // 01, 03, 23, 13.
      TetMidNodes& x = mesh.tet_mid[i];
      x = {x[2], x[1], x[0], x[3], x[5], x[4]};
    }
    ++count;
  }
  return count;
}

std::string ConformityReport::summary() const {
  std::ostringstream s;
  s << "inverted " << inverted << ", faces not on surface " << faces_not_on_surface << ", facets not on tets "
    << facets_not_on_tets << ", wrong-side regions " << wrong_side_regions << ", non-manifold faces "
    << non_manifold_faces << ", max relative volume error " << max_relative_volume_error;
  return s.str();
}

}  // namespace vd
