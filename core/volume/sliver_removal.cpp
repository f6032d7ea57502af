#include "volume/sliver_removal.h"

#include <algorithm>
#include <cmath>
#include <map>

#include "geometry/predicates.h"
#include "mesh/parallel.h"
#include "mesh/tet_faces.h"
#include "quality/tet_quality.h"
#include "surface/face_patches.h"
#include "volume/sliver_improvement.h"

namespace vd {
namespace {

// The smallest dihedral angles of a mesh in one pass over it.
struct SmallestAngles {
  double min_deg = 180;
  long below_5 = 0, below_10 = 0;
  std::vector<size_t> slivers;  // under the sliver angle, in mesh order
};

// `measures` (if given): each tetrahedron's smallest_dihedral_if_positive as
// listed, what the sliver pass's complex starts from. The two were measured
// apart, each of them 2.5 % of the instructions of a run on a box of 125k
// tetrahedra; where the listing is positive they are the same number.
SmallestAngles smallest_angles(const Mesh& m, double sliver_angle_deg, std::vector<double>* measures = nullptr) {
  constexpr long kChunk = 1 << 16;
  const long n = static_cast<long>(m.tets.size());
  std::vector<SmallestAngles> parts((n + kChunk - 1) / kChunk);
  if (measures) {
    // The complex takes the vector over, with room for what flips add.
    measures->reserve(sliver_pass_room(static_cast<size_t>(n)));
    measures->resize(static_cast<size_t>(n));
  }
  for_each_chunk(n, kChunk, [&](long c, long begin, long end) {
    SmallestAngles& p = parts[c];
    for (long t = begin; t < end; ++t) {
      const Tetrahedron& tet = m.tets[t];
      const Vec3 &a0 = m.points[tet.v[0]], &a1 = m.points[tet.v[1]], &a2 = m.points[tet.v[2]], &a3 = m.points[tet.v[3]];
      const double as_listed = smallest_dihedral_if_positive(a0, a1, a2, a3);
      if (measures) (*measures)[t] = as_listed;
      // Not positive as listed (-1): smallest_dihedral_deg looks at the
      // other orientation.
      const double a = as_listed >= 0 ? as_listed : smallest_dihedral_deg(a0, a1, a2, a3);
      p.min_deg = std::min(p.min_deg, a);
      p.below_5 += a < 5;
      p.below_10 += a < 10;
      if (a < sliver_angle_deg) p.slivers.push_back(static_cast<size_t>(t));
    }
  });
  SmallestAngles all;
  for (const SmallestAngles& p : parts) {
    all.min_deg = std::min(all.min_deg, p.min_deg);
    all.below_5 += p.below_5;
    all.below_10 += p.below_10;
    all.slivers.insert(all.slivers.end(), p.slivers.begin(), p.slivers.end());
  }
  if (n == 0) all.min_deg = 0;
  return all;
}

// Is facet `cap` of the two surface faces of a sliver (the other is
// `other`) a crease: its vertex off their shared edge between the edge's
// ends, seeing them at over kCreaseCapDeg?
constexpr double kCreaseCapDeg = 179.0;
bool is_crease_cap(const Mesh& m, const Triangle& cap, const Triangle& other) {
  for (int k = 0; k < 3; ++k) {
    const int r = cap.v[k], p = cap.v[(k + 1) % 3], q = cap.v[(k + 2) % 3];
    if (std::find(other.v.begin(), other.v.end(), r) != other.v.end()) continue;
    return corner_angle(m.points[r], m.points[p], m.points[q]) > kCreaseCapDeg * M_PI / 180.0;
  }
  return false;
}

// Case A over the given slivers (indices into m.tets).
// `measures` (if given, one per tetrahedron) are kept beside m.tets.
void remove_boundary_slivers(Mesh& m, const SliverOptions& o, const std::vector<size_t>& slivers,
                             SliverStats& stats, std::vector<double>* measures = nullptr) {
  std::map<std::array<int, 3>, int> facet_of;
  for (size_t f = 0; f < m.triangles.size(); ++f) facet_of[sorted_triple(m.triangles[f].v)] = static_cast<int>(f);
  std::vector<bool> removed(m.tets.size(), false);
  const double cos_ridge = std::cos(o.ridge_angle_deg * M_PI / 180.0);
  const double cos_flip_ridge = std::cos(o.flip_ridge_deg * M_PI / 180.0);

  // Removing one sliver exposes faces of its neighbours: repeat until stable.
  for (bool changed = true; changed;) {
    changed = false;
    for (size_t ti : slivers) {
      if (removed[ti]) continue;
      const Tetrahedron& t = m.tets[ti];
      int on_surface[4], n = 0, off_surface[4], k = 0;
      for (int i = 0; i < 4; ++i) {
        auto it = facet_of.find(sorted_triple(face_opposite(t.v, i)));
        if (it != facet_of.end()) on_surface[n++] = i;
        else off_surface[k++] = i;
      }
      if (n != 2) continue;
      const int f1 = facet_of.at(sorted_triple(face_opposite(t.v, on_surface[0])));
      const int f2 = facet_of.at(sorted_triple(face_opposite(t.v, on_surface[1])));
      Triangle a = m.triangles[f1], b = m.triangles[f2];
      // A facet of two faces' border that is itself a crease: its vertex off
      // the shared edge lies on that edge, seeing its ends at over
      // kCreaseCapDeg (c3tm_nefertiti.obj: 179.889 deg, 0.0008 off a 1.76
      // edge, under a 0.008 deg sliver that no other case reaches). Removing
      // the sliver moves the surface by that much at most; the border then
      // runs along the crease, and the two new facets are the other face's.
      const int crease_cap = a.face == b.face ? -1 : is_crease_cap(m, a, b) ? 0 : is_crease_cap(m, b, a) ? 1 : -1;
      if (crease_cap == 0) std::swap(a, b);  // b: the cap, a: the facet whose face the new ones take
      if (a.face != b.face && crease_cap < 0) continue;
      if (a.front != b.front || a.back != b.back) continue;
      // The other side of both facets must be the exterior.
      const int other = a.back == t.region ? a.front : a.back;
      if (other != 0 || (a.front != t.region && a.back != t.region)) continue;
      // New facets: the two other faces, oriented like the old ones (the
      // exterior, where the sliver was, on the same side).
      Triangle g[2];
      for (int j = 0; j < 2; ++j) {
        const int i = off_surface[j];
        g[j] = a;
        g[j].v = face_opposite(t.v, i);
        const bool opp_on_front = orientation(m.points[g[j].v[0]], m.points[g[j].v[1]], m.points[g[j].v[2]],
                                              m.points[t.v[i]]) > 0;
        const bool exterior_on_front = a.front == 0;
        if (opp_on_front != exterior_on_front) std::swap(g[j].v[1], g[j].v[2]);
      }
      // The ridge limit before and after, as for a flip: two facets folded
      // at a box's edge replaced by a flat pair would cut the edge off.
      const double ridge_after = dot(facet_normal(m.points, g[0]), facet_normal(m.points, g[1]));
      const double ridge_before = dot(facet_normal(m.points, a), facet_normal(m.points, b));
      const bool flat = (ridge_after >= cos_ridge && ridge_before >= cos_ridge) || crease_cap >= 0;
      // The face's chord height on CAD input, 0 elsewhere: how far the pair
      // may move the surface across a ridge over ridge_angle_deg.
      const double chord_height = face_value_or(o.face_chord_height, a.face, o.chord_height);
      // How far the surface moves: from the edge the two old facets share
      // (the vertices off the surface facets) to the edge the new ones share.
      if (!flat && !(chord_height > 0 && ridge_after >= cos_flip_ridge && ridge_before >= cos_flip_ridge &&
                     line_distance(m.points[t.v[off_surface[0]]], m.points[t.v[off_surface[1]]],
                                   m.points[t.v[on_surface[0]]], m.points[t.v[on_surface[1]]]) <= chord_height))
        continue;
      removed[ti] = true;
      stats.removed_crease_caps += crease_cap >= 0;
      facet_of.erase(sorted_triple(a.v));
      facet_of.erase(sorted_triple(b.v));
      m.triangles[f1] = g[0];
      m.triangles[f2] = g[1];
      facet_of[sorted_triple(g[0].v)] = f1;
      facet_of[sorted_triple(g[1].v)] = f2;
      ++stats.removed_boundary;
      stats.removed_across_ridges += !flat;
      changed = true;
    }
  }
  // In place: no second copy of the tetrahedra while the tetrahedralization
  // is still in memory.
  size_t kept = 0;
  for (size_t ti = 0; ti < m.tets.size(); ++ti)
    if (!removed[ti]) {
      if (measures) (*measures)[kept] = (*measures)[ti];
      m.tets[kept++] = m.tets[ti];
    }
  m.tets.resize(kept);
  if (measures) measures->resize(kept);
}

}  // namespace

void remove_boundary_slivers(Mesh& m, const SliverOptions& o, SliverStats& stats) {
  remove_boundary_slivers(m, o, smallest_angles(m, o.sliver_angle_deg).slivers, stats);
}

SliverStats remove_slivers(Mesh& m, const SliverOptions& o, const FacetApexes& apexes, QualitySummary* after_out,
                           const std::function<void()>& apexes_done) {
  SliverStats stats;
  stats.angle_deg = o.sliver_angle_deg;
  // No point moves in case A: its slivers are those counted here.
  const bool improve = o.flips || o.moves;
  std::vector<double> measures;
  const SmallestAngles before = smallest_angles(m, o.sliver_angle_deg, improve ? &measures : nullptr);
  stats.min_dihedral_before_deg = before.min_deg;
  stats.below_5_before = before.below_5;
  stats.below_10_before = before.below_10;
  stats.slivers_before = static_cast<long>(before.slivers.size());
  remove_boundary_slivers(m, o, before.slivers, stats, improve ? &measures : nullptr);
  if (improve) improve_slivers(m, o, apexes, stats, apexes_done, std::move(measures));
  else if (apexes_done) apexes_done();
  const QualitySummary after = summarize_quality(m, o.sliver_angle_deg);
  stats.min_dihedral_after_deg = after.min_dihedral_deg;
  stats.below_5_after = after.below_5_deg;
  stats.below_10_after = after.below_10_deg;
  stats.slivers_after = after.below_asked_deg;
  if (after_out) *after_out = after;
  return stats;
}

}  // namespace vd
