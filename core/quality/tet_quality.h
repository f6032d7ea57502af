// Shape measures of tetrahedra and their summary over a mesh: dihedral
// angles, radius ratio 3 r_in / R (1 for the regular tetrahedron, 0 for a
// flat one) and histograms of both.
#pragma once

#include <array>
#include <vector>

#include "mesh/mesh.h"

namespace vd {

// The six dihedral angles of (a, b, c, d), in degrees.
std::array<double, 6> dihedral_angles_deg(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d);
// The smallest of them, with one acos instead of six (0 for a flat one).
double smallest_dihedral_deg(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d);
// The same for a positive (a, b, c, d), or a negative value when its
// floating-point volume is not positive.
double smallest_dihedral_if_positive(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d);
// Cosine between the outward normals of the two faces at the smallest
// dihedral angle of a positive (a, b, c, d) (-2 when not positive): it orders
// tetrahedra as their smallest angle does, without the acos. Converted both
// ways by the two functions after it.
double smallest_dihedral_score(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d);
// The same score when it is above `floor`; otherwise some value at or below
// `floor`, found without the rest of the angles (a search that only asks
// "better than the best so far?" gets the same answers, sooner).
double smallest_dihedral_score_above(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d, double floor);
double dihedral_degrees_of_score(double score);
double dihedral_score_of_degrees(double deg);
double radius_ratio(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d);
// Whether summarize_quality counts the tetrahedron positive (its floating-
// point determinant, not the exact orientation: a flat one may differ).
bool positive_as_summarized(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d);

struct QualitySummary {
  long tets = 0;
  long inverted = 0;                 // non-positive volume
  double min_dihedral_deg = 180, max_dihedral_deg = 0;
  double min_radius_ratio = 1, mean_radius_ratio = 0;
  std::array<long, 18> dihedral_histogram{};      // 10-degree bins of all six angles
  std::array<long, 10> radius_ratio_histogram{};  // bins of 0.1
  long below_5_deg = 0, below_10_deg = 0;         // tets with a dihedral angle under 5 / 10 degrees
  long below_asked_deg = 0;                       // ... under summarize_quality's count_below_deg
};

// count_below_deg: a third angle to count tetrahedra under (below_asked_deg),
// so that a caller needing one does not measure the mesh again.
QualitySummary summarize_quality(const Mesh& mesh, double count_below_deg = 0);

}  // namespace vd
