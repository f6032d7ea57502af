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
  // Sorted by the edge's lower vertex with one counting pass (the pairs go
  // out in facet order), then each vertex's few by the upper one, stably:
  // the order std::sort gives the (key, facet) pairs, without its
  // comparisons (the sort was most of the adjacency's cost, which the size
  // refinement rebuilds after every sweep of flips).
  size_t vertices = 0;
  for (const Triangle& t : facets)
    for (int v : t.v) vertices = std::max(vertices, static_cast<size_t>(v) + 1);
  std::vector<size_t> start(vertices + 1, 0);
  for (const Triangle& t : facets)
    for (int i = 0; i < 3; ++i) ++start[static_cast<size_t>(std::min(t.v[i], t.v[(i + 1) % 3])) + 1];
  for (size_t v = 0; v < vertices; ++v) start[v + 1] += start[v];
  pairs.resize(3 * facets.size());
  std::vector<size_t> fill(start.begin(), start.end() - 1);
  for (size_t f = 0; f < facets.size(); ++f)
    for (int i = 0; i < 3; ++i) {
      const int a = facets[f].v[i], b = facets[f].v[(i + 1) % 3];
      pairs[fill[static_cast<size_t>(std::min(a, b))]++] = {edge_key(a, b), static_cast<int>(f)};
    }
  for (size_t v = 0; v < vertices; ++v) {
    if (start[v + 1] - start[v] > 32) {  // a vertex of many edges (a fan's apex): (key, facet) order
      std::sort(pairs.begin() + static_cast<long>(start[v]), pairs.begin() + static_cast<long>(start[v + 1]));
      continue;
    }
    for (size_t i = start[v] + 1; i < start[v + 1]; ++i)  // insertion sort: stable, and runs are short
      for (size_t j = i; j > start[v] && pairs[j - 1].first > pairs[j].first; --j) std::swap(pairs[j - 1], pairs[j]);
  }
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
