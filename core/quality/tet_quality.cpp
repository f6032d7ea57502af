#include "quality/tet_quality.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "mesh/parallel.h"

namespace vd {

namespace {

// Unit normals of the faces opposite vertices 0..3 of p, each turned away
// from its opposite vertex (whatever the tetrahedron's orientation); a
// degenerate face gives the zero vector. `twice_area[i]`: the length of
// face i's normal before it was made a unit one; `triple`: (p1 - p0) x
// (p2 - p0) . (p3 - p0), six times the signed volume. The same numbers,
// bit for bit, as radius_ratio's areas and volume, which summarize_quality
// took from them instead of working them out again (with the unit frame,
// a tenth of its instructions).
void outward_unit_normals(const Vec3 (&p)[4], Vec3 (&n)[4], double (&twice_area)[4], double& triple) {
  for (int i = 0; i < 4; ++i) {
    int k[3], c = 0;
    for (int j = 0; j < 4; ++j)
      if (j != i) k[c++] = j;
    Vec3 nf = cross(p[k[1]] - p[k[0]], p[k[2]] - p[k[0]]);
    const double side = dot(nf, p[i] - p[k[0]]);
    if (i == 3) triple = side;
    if (side > 0) nf = -1.0 * nf;
    twice_area[i] = norm(nf);
    n[i] = twice_area[i] > 0 ? (1.0 / twice_area[i]) * nf : nf;
  }
}

void outward_unit_normals(const Vec3 (&p)[4], Vec3 (&n)[4]) {
  double twice_area[4], triple;
  outward_unit_normals(p, n, twice_area, triple);
}

// The radius ratio of a tetrahedron in the unit frame whose volume and
// total face area are known.
double radius_ratio_of(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d, double vol, double area) {
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

// A tetrahedron far from unit size, relative to its first corner and scaled
// by a power of two (exact) to a longest edge between 1 and 2: the normals'
// squared lengths are fourth powers of the edges, which underflowed to zero
// for a mesh 1e-85 across (every angle 90 degrees) and overflowed 1e80
// across. Within 2^+-120 of unit size it is left as it is, to the last bit.
void to_unit_frame(Vec3 (&p)[4]) {
  double reach = 0;
  for (int i = 1; i < 4; ++i)
    reach = std::max({reach, std::abs(p[i].x - p[0].x), std::abs(p[i].y - p[0].y), std::abs(p[i].z - p[0].z)});
  if (!(reach > 0) || !std::isfinite(reach)) return;
  const int k = std::ilogb(reach);
  if (k >= -120 && k <= 120) return;
  for (int i = 1; i < 4; ++i) {
    const Vec3 e = p[i] - p[0];
    p[i] = Vec3{std::ldexp(e.x, -k), std::ldexp(e.y, -k), std::ldexp(e.z, -k)};
  }
  p[0] = Vec3{};
}

// The sign summarize_quality counts inverted tetrahedra by (the unit frame's
// floating-point determinant).
bool positive_in_unit_frame(const Vec3 (&p)[4]) { return dot(cross(p[1] - p[0], p[2] - p[0]), p[3] - p[0]) > 0; }

}  // namespace

bool positive_as_summarized(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
  Vec3 p[4] = {a, b, c, d};
  to_unit_frame(p);
  return positive_in_unit_frame(p);
}

std::array<double, 6> dihedral_angles_deg(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
  Vec3 p[4] = {a, b, c, d};
  to_unit_frame(p);
  Vec3 n[4];
  outward_unit_normals(p, n);
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

double smallest_dihedral_score_above(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d, double floor) {
  const Vec3 ab = b - a, ac = c - a, ad = d - a;
  if (dot(cross(ab, ac), ad) <= 0) return -2.0;
  // Outward normals of the faces opposite d, c, b and a of a positive tetrahedron.
  const Vec3 n[4] = {cross(ac, ab), cross(ab, ad), cross(ad, ac), cross(c - b, d - b)};
  double len[4];
  for (int i = 0; i < 4; ++i) {
    len[i] = norm(n[i]);
    if (!(len[i] > 0)) return -2.0;
  }
  // The dihedral angle at an edge is pi minus the angle between the outward
  // normals of its two faces: the smallest angle has the smallest cosine.
  double lowest = 1.0;
  for (int i = 0; i < 4; ++i)
    for (int j = i + 1; j < 4; ++j) {
      lowest = std::min(lowest, dot(n[i], n[j]) / (len[i] * len[j]));
      if (lowest <= floor) return lowest;
    }
  return std::clamp(lowest, -1.0, 1.0);
}

double smallest_dihedral_score(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
  return smallest_dihedral_score_above(a, b, c, d, -std::numeric_limits<double>::infinity());
}

double dihedral_degrees_of_score(double score) {
  return score < -1.0 ? -1.0 : 180.0 - std::acos(score) * 180.0 / M_PI;
}

double dihedral_score_of_degrees(double deg) { return deg < 0 ? -2.0 : -std::cos(deg * M_PI / 180.0); }

double smallest_dihedral_if_positive(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
  return dihedral_degrees_of_score(smallest_dihedral_score(a, b, c, d));
}

double smallest_dihedral_deg(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
  // Either orientation: the same tetrahedron listed positively. A flat one
  // (no positive listing in floating point) has a zero angle.
  const bool negative = dot(cross(b - a, c - a), d - a) < 0;
  return std::max(0.0, negative ? smallest_dihedral_if_positive(a, c, b, d) : smallest_dihedral_if_positive(a, b, c, d));
}

double radius_ratio(const Vec3& a0, const Vec3& b0, const Vec3& c0, const Vec3& d0) {
  Vec3 p[4] = {a0, b0, c0, d0};
  to_unit_frame(p);
  const Vec3 &a = p[0], &b = p[1], &c = p[2], &d = p[3];
  const double vol = std::abs(dot(cross(b - a, c - a), d - a)) / 6.0;
  const double area = 0.5 * (norm(cross(b - a, c - a)) + norm(cross(b - a, d - a)) + norm(cross(c - a, d - a)) +
                             norm(cross(c - b, d - b)));
  return radius_ratio_of(a, b, c, d, vol, area);
}

namespace {

// The cosines between outward face normals whose dihedral angle, 180 minus
// their angle, is 10, 20, ... 170 degrees: an angle is in bin k when its
// cosine is at least the k-th of them. Bins by cosine save five of the six
// acos per tetrahedron.
struct BinEdges {
  double cosine[17];
  // The cosines of 60, 90 and 120 degrees exactly (0.5, 0, -0.5): cos of
  // 90 degrees in radians is 6.1e-17, and a cube's right angles, whose
  // cosine comes out 0, fell into 80-90 instead of 90-100 (48 of a unit
  // cube's mesh against numpy's histogram of the angles).
  BinEdges() {
    for (int k = 1; k <= 17; ++k) {
      const double c = std::cos((180.0 - 10.0 * k) * M_PI / 180.0);
      const double half = std::round(2 * c) / 2;
      cosine[k - 1] = std::abs(c - half) < 1e-12 ? half : c;
    }
    for (int k = 0; k < 17; ++k)
      for (int j = slot(cosine[k]) + 1; j < kSlots; ++j) ++first_possible[j];
  }
  // The number of edges at or under c, as std::upper_bound counts them:
  // from the edges below c's slot on (a slot holds at most one edge), not by
  // a binary search per angle (six per tetrahedron: a tenth of the summary).
  int bin(double c) const {
    if (!(c >= -1.0 && c <= 1.0)) return static_cast<int>(std::upper_bound(cosine, cosine + 17, c) - cosine);
    int k = first_possible[slot(c)];
    while (k < 17 && cosine[k] <= c) ++k;
    return k;
  }

 private:
  // Slots of 1/32 over [-1, 1]; an edge in a slot below c's is under c.
  static constexpr int kSlots = 64;
  static int slot(double c) { return std::min(kSlots - 1, static_cast<int>((c + 1.0) * 32.0)); }
  int first_possible[kSlots] = {};
};

double degrees_between_faces(double cosine) { return 180.0 - std::acos(cosine) * 180.0 / M_PI; }

// One chunk's figures; the mean radius ratio's sum kept apart. The angle
// in degrees grows with the cosine, so the chunk's extremes are converted
// once at the end, and a tetrahedron's smallest angle only when it may be
// under 10 degrees or asked_deg (the acos were a tenth of the summary).
void summarize_into(const Mesh& m, long begin, long end, const BinEdges& edges, double asked_deg, QualitySummary& q,
                    double& sum_rr) {
  const double maybe_under = std::cos((180.0 - (std::max(10.0, asked_deg) + 0.5)) * M_PI / 180.0);
  double lowest = 1, highest = -1;
  for (long i = begin; i < end; ++i) {
    const Tetrahedron& t = m.tets[i];
    Vec3 p[4] = {m.points[t.v[0]], m.points[t.v[1]], m.points[t.v[2]], m.points[t.v[3]]};
    to_unit_frame(p);
    ++q.tets;
    // The same normals as dihedral_angles_deg, so that the extremes agree
    // with it to the last bit; the triple product is positive_in_unit_frame's.
    Vec3 n[4];
    double twice_area[4], triple;
    outward_unit_normals(p, n, twice_area, triple);
    if (!(triple > 0)) ++q.inverted;
    double lo = 1, hi = -1;
    for (int a = 0; a < 4; ++a)
      for (int b = a + 1; b < 4; ++b) {
        const double c = std::clamp(dot(n[a], n[b]), -1.0, 1.0);
        lo = std::min(lo, c), hi = std::max(hi, c);
        q.dihedral_histogram[edges.bin(c)]++;
      }
    lowest = std::min(lowest, lo), highest = std::max(highest, hi);
    if (lo < maybe_under) {
      const double smallest = degrees_between_faces(lo);
      q.below_5_deg += smallest < 5;
      q.below_10_deg += smallest < 10;
      q.below_asked_deg += smallest < asked_deg;
    }
    // radius_ratio's sums, in its order (p is in the unit frame already).
    const double area = 0.5 * (twice_area[3] + twice_area[2] + twice_area[1] + twice_area[0]);
    const double rr = radius_ratio_of(p[0], p[1], p[2], p[3], std::abs(triple) / 6.0, area);
    sum_rr += rr;
    q.min_radius_ratio = std::min(q.min_radius_ratio, rr);
    q.radius_ratio_histogram[std::min(9, std::max(0, int(rr * 10.0)))]++;
  }
  if (end > begin) {
    q.min_dihedral_deg = std::min(q.min_dihedral_deg, degrees_between_faces(lowest));
    q.max_dihedral_deg = std::max(q.max_dihedral_deg, degrees_between_faces(highest));
  }
}

}  // namespace

QualitySummary summarize_quality(const Mesh& m, double count_below_deg) {
  static const BinEdges edges;
  constexpr long kChunk = 1 << 16;
  const long n = static_cast<long>(m.tets.size());
  std::vector<QualitySummary> parts((n + kChunk - 1) / kChunk);
  std::vector<double> sums(parts.size(), 0.0);
  for_each_chunk(n, kChunk, [&](long c, long begin, long end) {
    summarize_into(m, begin, end, edges, count_below_deg, parts[c], sums[c]);
  });
  QualitySummary q;
  double sum_rr = 0;
  for (size_t c = 0; c < parts.size(); ++c) {
    const QualitySummary& p = parts[c];
    q.tets += p.tets;
    q.inverted += p.inverted;
    q.min_dihedral_deg = std::min(q.min_dihedral_deg, p.min_dihedral_deg);
    q.max_dihedral_deg = std::max(q.max_dihedral_deg, p.max_dihedral_deg);
    q.min_radius_ratio = std::min(q.min_radius_ratio, p.min_radius_ratio);
    for (size_t k = 0; k < q.dihedral_histogram.size(); ++k) q.dihedral_histogram[k] += p.dihedral_histogram[k];
    for (size_t k = 0; k < q.radius_ratio_histogram.size(); ++k)
      q.radius_ratio_histogram[k] += p.radius_ratio_histogram[k];
    q.below_5_deg += p.below_5_deg;
    q.below_10_deg += p.below_10_deg;
    q.below_asked_deg += p.below_asked_deg;
    sum_rr += sums[c];
  }
  if (q.tets) q.mean_radius_ratio = sum_rr / q.tets;
  else q.min_dihedral_deg = q.max_dihedral_deg = q.min_radius_ratio = 0;
  return q;
}

}  // namespace vd
