#include "quality/tet_quality.h"

#include <algorithm>
#include <cmath>

namespace vd {

std::array<double, 6> dihedral_angles_deg(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
  const Vec3 p[4] = {a, b, c, d};
  // Outward-agnostic face normals: normal of the face opposite vertex i.
  auto face_normal = [&](int i) {
    int k[3], c2 = 0;
    for (int j = 0; j < 4; ++j)
      if (j != i) k[c2++] = j;
    Vec3 n = cross(p[k[1]] - p[k[0]], p[k[2]] - p[k[0]]);
    // Orient it away from the opposite vertex.
    if (dot(n, p[i] - p[k[0]]) > 0) n = -1.0 * n;
    return normalized(n);
  };
  Vec3 n[4];
  for (int i = 0; i < 4; ++i) n[i] = face_normal(i);
  // The dihedral angle at the edge shared by faces i and j is pi minus the
  // angle between their outward normals.
  std::array<double, 6> out{};
  int e = 0;
  for (int i = 0; i < 4; ++i)
    for (int j = i + 1; j < 4; ++j) {
      const double c2 = std::clamp(dot(n[i], n[j]), -1.0, 1.0);
      out[e++] = 180.0 - std::acos(c2) * 180.0 / M_PI;
    }
  return out;
}

double radius_ratio(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
  const double vol = std::abs(dot(cross(b - a, c - a), d - a)) / 6.0;
  const double area = 0.5 * (norm(cross(b - a, c - a)) + norm(cross(b - a, d - a)) + norm(cross(c - a, d - a)) +
                             norm(cross(c - b, d - b)));
  if (area <= 0) return 0;
  const double r_in = 3.0 * vol / area;
  // Circumradius: |a|^2-weighted formula relative to a.
  const Vec3 u = b - a, v = c - a, w = d - a;
  const double det = 2.0 * dot(u, cross(v, w));
  if (det == 0) return 0;
  const Vec3 centre = (1.0 / det) * (dot(u, u) * cross(v, w) + dot(v, v) * cross(w, u) + dot(w, w) * cross(u, v));
  const double R = norm(centre);
  return R > 0 ? 3.0 * r_in / R : 0;
}

QualitySummary summarize_quality(const Mesh& m) {
  QualitySummary q;
  double sum_rr = 0;
  for (const Tetrahedron& t : m.tets) {
    const Vec3 &a = m.points[t.v[0]], &b = m.points[t.v[1]], &c = m.points[t.v[2]], &d = m.points[t.v[3]];
    ++q.tets;
    if (dot(cross(b - a, c - a), d - a) <= 0) ++q.inverted;
    const auto angles = dihedral_angles_deg(a, b, c, d);
    double lo = 180;
    for (double x : angles) {
      lo = std::min(lo, x);
      q.min_dihedral_deg = std::min(q.min_dihedral_deg, x);
      q.max_dihedral_deg = std::max(q.max_dihedral_deg, x);
      q.dihedral_histogram[std::min(17, std::max(0, int(x / 10.0)))]++;
    }
    q.below_5_deg += lo < 5;
    q.below_10_deg += lo < 10;
    const double rr = radius_ratio(a, b, c, d);
    sum_rr += rr;
    q.min_radius_ratio = std::min(q.min_radius_ratio, rr);
    q.radius_ratio_histogram[std::min(9, std::max(0, int(rr * 10.0)))]++;
  }
  if (q.tets) q.mean_radius_ratio = sum_rr / q.tets;
  else q.min_dihedral_deg = q.max_dihedral_deg = q.min_radius_ratio = 0;
  return q;
}

}  // namespace vd
