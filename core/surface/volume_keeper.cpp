#include "surface/volume_keeper.h"

#include <algorithm>
#include <cmath>
#include <utility>

#include "surface/edge_map.h"
#include "volume/region_tetrahedra.h"

namespace vd {

VolumeKeeper::VolumeKeeper(const Mesh& m, std::vector<double> target, double limit)
    : target_(std::move(target)), limit_(limit) {
  if (!active()) return;
  volume_ = enclosed_volumes(m);
  volume_.resize(std::max(volume_.size(), target_.size()), 0.0);
}

double VolumeKeeper::error(int region) const {
  return kept(region) ? volume_[region] / target_[region] - 1.0 : 0.0;
}

// enclosed_volumes' convention: a facet's normal points out of `back`.
// One entry per region: a move is judged by its whole change.
void VolumeKeeper::add(const Triangle& sides, double change, std::vector<std::pair<int, double>>& out) const {
  const auto book = [&out](int region, double dv) {
    for (auto& [r, sum] : out)
      if (r == region) {
        sum += dv;
        return;
      }
    out.emplace_back(region, dv);
  };
  if (kept(sides.back)) book(sides.back, change);
  if (kept(sides.front)) book(sides.front, -change);
}

bool VolumeKeeper::take_split(const Mesh& m, int p, int q, const std::vector<int>& sharing, const Vec3& point) {
  if (!active()) return true;
  std::vector<std::pair<int, double>> change;
  for (const int f : sharing) {
    const Triangle& t = m.triangles[f];
    const int a = has_directed_edge(t, p, q) ? p : q, b = a == p ? q : p;
    const int c = opposite_vertex(t, p, q);
    // (a, b, c) becomes (a, point, c) and (point, b, c): their volumes
    // against a as origin.
    add(t, tet_volume(m.points[a], point, m.points[b], m.points[c]), change);
  }
  for (const auto& [region, dv] : change) {
    const double before = std::abs(error(region));
    const double after = std::abs((volume_[region] + dv) / target_[region] - 1.0);
    if (after > limit_ && after > before) return false;
  }
  for (const auto& [region, dv] : change) volume_[region] += dv;
  return true;
}

void VolumeKeeper::record_flip(const Mesh& m, const Triangle& t, const Triangle& t2, const Triangle& a,
                               const Triangle& b) {
  if (!active()) return;
  const Vec3& o = m.points[t.v[0]];
  auto cone = [&](const Triangle& x) { return tet_volume(o, m.points[x.v[0]], m.points[x.v[1]], m.points[x.v[2]]); };
  std::vector<std::pair<int, double>> change;
  add(t, cone(a) + cone(b) - cone(t) - cone(t2), change);
  for (const auto& [region, dv] : change) volume_[region] += dv;
}

}  // namespace vd
