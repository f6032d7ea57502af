#include "surface/edge_map.h"

#include <algorithm>

namespace vd {

void FacetList::push_back(int f) {
  if (n_ < 2) {
    small_[n_++] = f;
    return;
  }
  if (n_ == 2) big_.assign(small_, small_ + 2);
  big_.push_back(f);
  ++n_;
}

void FacetList::erase(int f) {
  if (n_ <= 2) {
    int kept = 0;
    for (int i = 0; i < n_; ++i)
      if (small_[i] != f) small_[kept++] = small_[i];
    n_ = kept;
    return;
  }
  big_.erase(std::remove(big_.begin(), big_.end(), f), big_.end());
  n_ = static_cast<int>(big_.size());
  if (n_ <= 2) {
    std::copy(big_.begin(), big_.end(), small_);
    big_ = {};
  }
}

EdgeMap::EdgeMap(const std::vector<Triangle>& facets) {
  map_.reserve(facets.size() * 2);
  for (size_t f = 0; f < facets.size(); ++f) add(static_cast<int>(f), facets[f]);
}

void EdgeMap::add(int facet, const Triangle& t) {
  for (int i = 0; i < 3; ++i) map_[edge_key(t.v[i], t.v[(i + 1) % 3])].push_back(facet);
}

void EdgeMap::remove(int facet, const Triangle& t) {
  for (int i = 0; i < 3; ++i) {
    auto it = map_.find(edge_key(t.v[i], t.v[(i + 1) % 3]));
    if (it == map_.end()) continue;
    it->second.erase(facet);
    if (it->second.empty()) map_.erase(it);
  }
}

const FacetList& EdgeMap::facets(int a, int b) const {
  static const FacetList none;
  auto it = map_.find(edge_key(a, b));
  return it == map_.end() ? none : it->second;
}

EdgeFacetPairs::EdgeFacetPairs(const std::vector<Triangle>& facets) {
  pairs.reserve(3 * facets.size());
  for (size_t f = 0; f < facets.size(); ++f)
    for (int i = 0; i < 3; ++i)
      pairs.emplace_back(edge_key(facets[f].v[i], facets[f].v[(i + 1) % 3]), static_cast<int>(f));
  std::sort(pairs.begin(), pairs.end());
}

std::vector<int> EdgeFacetPairs::facets(std::uint64_t key) const {
  std::vector<int> out;
  for (auto it = std::lower_bound(pairs.begin(), pairs.end(), std::make_pair(key, -1));
       it != pairs.end() && it->first == key; ++it)
    out.push_back(it->second);
  return out;
}

bool EdgeFacetPairs::contains(std::uint64_t key) const {
  const auto it = std::lower_bound(pairs.begin(), pairs.end(), std::make_pair(key, -1));
  return it != pairs.end() && it->first == key;
}

std::vector<double> surface_vertex_sizes(const Mesh& m, const EdgeMap& edges) {
  std::vector<double> sum(m.points.size(), 0.0);
  std::vector<int> count(m.points.size(), 0);
  for (const auto& [key, list] : edges.all()) {
    const auto [a, b] = edge_of_key(key);
    const double len = norm(m.points[a] - m.points[b]);
    sum[a] += len, sum[b] += len;
    ++count[a], ++count[b];
  }
  for (size_t v = 0; v < sum.size(); ++v) {
    sum[v] = count[v] ? sum[v] / count[v] : 0.0;
    if (v < m.point_size.size() && m.point_size[v] > 0) sum[v] = m.point_size[v];
  }
  return sum;
}

bool has_directed_edge(const Triangle& t, int a, int b) {
  for (int i = 0; i < 3; ++i)
    if (t.v[i] == a && t.v[(i + 1) % 3] == b) return true;
  return false;
}

int opposite_vertex(const Triangle& t, int a, int b) {
  for (int v : t.v)
    if (v != a && v != b) return v;
  return -1;
}

}  // namespace vd
