#include "volume/size_field.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <queue>

#include "surface/edge_map.h"

namespace vd {

SizeField::SizeField(const Mesh& m, const SizeFieldOptions& o)
    : SizeField(m, surface_vertex_sizes(m, EdgeMap(m.triangles)), o) {}

SizeField::SizeField(const Mesh& m, const std::vector<double>& hv, const SizeFieldOptions& o) : uniform_(o.uniform) {
  Vec3 lo{1e300, 1e300, 1e300}, hi{-1e300, -1e300, -1e300};
  double hmin = std::numeric_limits<double>::infinity();
  for (size_t v = 0; v < m.points.size(); ++v) {
    if (hv[v] <= 0) continue;
    for (int i = 0; i < 3; ++i) lo[i] = std::min(lo[i], m.points[v][i]), hi[i] = std::max(hi[i], m.points[v][i]);
    hmin = std::min(hmin, hv[v]);
  }
  if (!std::isfinite(hmin)) {
    smallest_ = uniform_;
    return;
  }
  const double diag = norm(hi - lo);
  // About 48 cells along the longest side: the field is smooth by design.
  step_ = std::max({hi.x - lo.x, hi.y - lo.y, hi.z - lo.z}) / 48.0;
  if (step_ <= 0) step_ = diag > 0 ? diag : 1.0;
  origin_ = lo - step_ * Vec3{1, 1, 1};
  for (int i = 0; i < 3; ++i) n_[i] = static_cast<int>(std::ceil((hi[i] - lo[i]) / step_)) + 3;
  const double cap = uniform_ > 0 ? uniform_ : std::max(diag / 4.0, hmin);
  h_.assign(static_cast<size_t>(n_[0]) * n_[1] * n_[2], cap);
  // Seed the nodes around each surface vertex, then relax outwards.
  using Item = std::pair<double, size_t>;
  std::priority_queue<Item, std::vector<Item>, std::greater<Item>> queue;
  for (size_t v = 0; v < m.points.size(); ++v) {
    if (hv[v] <= 0) continue;
    const Vec3 g = (1.0 / step_) * (m.points[v] - origin_);
    const int i0 = static_cast<int>(g.x), j0 = static_cast<int>(g.y), k0 = static_cast<int>(g.z);
    for (int k = k0; k <= k0 + 1; ++k)
      for (int j = j0; j <= j0 + 1; ++j)
        for (int i = i0; i <= i0 + 1; ++i) {
          const Vec3 node_point = origin_ + step_ * Vec3{double(i), double(j), double(k)};
          const double h = std::min(cap, hv[v] + o.gradation * norm(node_point - m.points[v]));
          const size_t id = node_index(i, j, k);
          if (h < h_[id]) {
            h_[id] = h;
            queue.emplace(h, id);
          }
        }
  }
  // The step to a neighbour node by how many of its coordinates differ,
  // worked out as the loop below did per neighbour.
  double rise[4] = {0, 0, 0, 0};
  for (int s = 1; s <= 3; ++s) rise[s] = o.gradation * step_ * std::sqrt(double(s));
  while (!queue.empty()) {
    const auto [h, id] = queue.top();
    queue.pop();
    if (h > h_[id]) continue;
    // No node holds more than the cap, and the nearest neighbour would get
    // h + rise[1] at least: nothing to lower (most of a box's nodes near
    // its surface, where the field starts near the cap).
    if (!(h + rise[1] < cap)) continue;
    const int i = static_cast<int>(id % n_[0]), j = static_cast<int>((id / n_[0]) % n_[1]);
    const int k = static_cast<int>(id / (static_cast<size_t>(n_[0]) * n_[1]));
    for (int dk = -1; dk <= 1; ++dk)
      for (int dj = -1; dj <= 1; ++dj)
        for (int di = -1; di <= 1; ++di) {
          const int a = i + di, b = j + dj, c = k + dk;
          if (a < 0 || b < 0 || c < 0 || a >= n_[0] || b >= n_[1] || c >= n_[2]) continue;
          const double next = h + rise[di * di + dj * dj + dk * dk];
          const size_t nid = node_index(a, b, c);
          if (next < h_[nid]) {
            h_[nid] = next;
            queue.emplace(next, nid);
          }
        }
  }
  smallest_ = *std::min_element(h_.begin(), h_.end());
}

double SizeField::at(const Vec3& p) const {
  if (h_.empty()) return uniform_;
  Vec3 g = (1.0 / step_) * (p - origin_);
  int c[3];
  double t[3];
  for (int i = 0; i < 3; ++i) {
    g[i] = std::clamp(g[i], 0.0, double(n_[i] - 1) - 1e-9);
    c[i] = static_cast<int>(g[i]);
    t[i] = g[i] - c[i];
  }
  // The clamp keeps c[i] + 1 inside the grid (n_[i] >= 3), so the corners
  // are the node at c and its neighbours one step along each axis.
  const size_t base = node_index(c[0], c[1], c[2]);
  const size_t step[3] = {1, static_cast<size_t>(n_[0]), static_cast<size_t>(n_[0]) * n_[1]};
  double h = 0;
  for (int dk = 0; dk <= 1; ++dk)
    for (int dj = 0; dj <= 1; ++dj)
      for (int di = 0; di <= 1; ++di) {
        const double w = (di ? t[0] : 1 - t[0]) * (dj ? t[1] : 1 - t[1]) * (dk ? t[2] : 1 - t[2]);
        h += w * h_[base + di * step[0] + dj * step[1] + dk * step[2]];
      }
  return h;
}

}  // namespace vd
