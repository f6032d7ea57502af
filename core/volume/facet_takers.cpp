#include "volume/facet_takers.h"

#include <algorithm>
#include <cmath>

#include "geometry/cell_key.h"
#include "geometry/predicates.h"

namespace vd {


FacetTakers::FacetTakers(const Mesh& m, const DelaunayTetrahedralization& dt) : points_(m.points) {
  std::vector<Ball> balls;  // the smaller circumsphere of each kept facet
  const std::vector<std::array<int, 2>> apexes = dt.facet_apexes(m.triangles);
  for (size_t k = 0; k < m.triangles.size(); ++k) {
    const Triangle& t = m.triangles[k];
    const std::array<int, 2>& apex = apexes[k];
    if (apex[0] < 0 || apex[1] < 0) continue;  // on the hull, or not a face (nothing to take)
    Facet f{t.v, apex};
    const Vec3 &a = points_[f.v[0]], &b = points_[f.v[1]], &c = points_[f.v[2]];
    // Apex 0 on the positive side of (v0, v1, v2), apex 1 on the other.
    if (orientation(a, b, c, points_[f.apex[0]]) < 0) std::swap(f.apex[0], f.apex[1]);
    const Ball b0 = circumsphere(a, b, c, points_[f.apex[0]]), b1 = circumsphere(a, b, c, points_[f.apex[1]]);
    facets_.push_back(f);
    balls.push_back(b0.radius < b1.radius ? b0 : b1);
  }
  if (facets_.empty()) return;
  // The finest cells: twice the median ball radius.
  std::vector<double> radii;
  for (const Ball& b : balls) radii.push_back(b.radius);
  std::nth_element(radii.begin(), radii.begin() + static_cast<long>(radii.size() / 2), radii.end());
  finest_ = std::max(2.0 * radii[radii.size() / 2], 1e-300);
  for (size_t i = 0; i < facets_.size(); ++i) {
    const double r = safe_radius(balls[i]);
    if (!std::isfinite(r)) {
      everywhere_.push_back(static_cast<int>(i));
      continue;
    }
    size_t level = 0;
    double side = finest_;
    while (side < 2 * r) side *= 4, ++level;
    if (levels_.size() <= level) levels_.resize(level + 1);
    // Corners of the ball's box: the cells it meets (at most two per axis).
    std::vector<std::uint64_t> keys;
    for (int corner = 0; corner < 8; ++corner) {
      const Vec3 q = balls[i].centre + Vec3{corner & 1 ? r : -r, corner & 2 ? r : -r, corner & 4 ? r : -r};
      keys.push_back(pack_cell(cell_coords(q, side)));
    }
    std::sort(keys.begin(), keys.end());
    keys.erase(std::unique(keys.begin(), keys.end()), keys.end());
    for (std::uint64_t k : keys) levels_[level][k].push_back(static_cast<int>(i));
  }
}

bool FacetTakers::takes(const Facet& f, const Vec3& p) const {
  const Vec3 &a = points_[f.v[0]], &b = points_[f.v[1]], &c = points_[f.v[2]];
  return perturbed_side_of_circumsphere(a, b, c, points_[f.apex[0]], p) == SphereSide::inside &&
         perturbed_side_of_circumsphere(a, c, b, points_[f.apex[1]], p) == SphereSide::inside;
}

bool FacetTakers::takes_a_facet(const Vec3& p) const {
  for (int i : everywhere_)
    if (takes(facets_[i], p)) return true;
  double side = finest_;
  for (const auto& level : levels_) {
    const auto it = level.find(pack_cell(cell_coords(p, side)));
    if (it != level.end())
      for (int i : it->second)
        if (takes(facets_[i], p)) return true;
    side *= 4;
  }
  return false;
}

}  // namespace vd
