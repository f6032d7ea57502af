#include "surface/edge_map.h"

#include <algorithm>

namespace vd {

// Empty slots, 2^k of them for the smallest k >= 4 that gives `at_least`.
void EdgeMap::empty_slots(size_t at_least) {
  int bits = 4;
  while ((size_t{1} << bits) < at_least) ++bits;
  slots_.assign(size_t{1} << bits, Slot{});
  shift_ = 64 - bits;
}

EdgeMap::EdgeMap(const std::vector<Triangle>& facets) {
  // A closed surface has 3/2 edges a facet; room for them at most half full.
  empty_slots(3 * facets.size());
  for (size_t f = 0; f < facets.size(); ++f) add(static_cast<int>(f), facets[f]);
}

size_t EdgeMap::find(std::uint64_t key) const {
  if (slots_.empty()) return kNone;
  const size_t mask = slots_.size() - 1;
  for (size_t i = home(key);; i = (i + 1) & mask) {
    if (slots_[i].key == key) return i;
    if (slots_[i].key == kEmpty) return kNone;
  }
}

EdgeMap::Slot& EdgeMap::find_or_insert(std::uint64_t key) {
  if (2 * (size_ + 1) > slots_.size()) grow();
  const size_t mask = slots_.size() - 1;
  size_t i = home(key);
  while (slots_[i].key != key && slots_[i].key != kEmpty) i = (i + 1) & mask;
  if (slots_[i].key == kEmpty) {
    slots_[i].key = key;
    ++size_;
  }
  return slots_[i];
}

void EdgeMap::grow() {
  std::vector<Slot> old = std::move(slots_);
  empty_slots(2 * old.size());
  const size_t mask = slots_.size() - 1;
  for (const Slot& s : old) {
    if (s.key == kEmpty) continue;
    size_t i = home(s.key);
    while (slots_[i].key != kEmpty) i = (i + 1) & mask;
    slots_[i] = s;
  }
}

// Backward shift: the slots after i that probed past it move up, so that no
// lookup meets a hole before its key (no tombstones to clean up later).
void EdgeMap::erase_slot(size_t i) {
  const size_t mask = slots_.size() - 1;
  for (size_t j = (i + 1) & mask; slots_[j].key != kEmpty; j = (j + 1) & mask) {
    const size_t k = home(slots_[j].key);
    const bool stays = i <= j ? (i < k && k <= j) : (i < k || k <= j);
    if (stays) continue;
    slots_[i] = slots_[j];
    i = j;
  }
  slots_[i] = Slot{};
  --size_;
}

FacetList EdgeMap::list(const Slot& s) const {
  FacetList l;
  l.n_ = s.n;
  if (s.n <= 2) l.small_[0] = s.a, l.small_[1] = s.b;
  else l.big_ = big_[static_cast<size_t>(s.a)].data();
  return l;
}

void EdgeMap::push(Slot& s, int facet) {
  if (s.n == 0) {
    s.a = facet;
  } else if (s.n == 1) {
    s.b = facet;
  } else if (s.n == 2) {
    int index;
    if (free_big_.empty()) {
      index = static_cast<int>(big_.size());
      big_.emplace_back();
    } else {
      index = free_big_.back();
      free_big_.pop_back();
    }
    big_[static_cast<size_t>(index)] = {s.a, s.b, facet};
    s.a = index;
    s.b = -1;
  } else {
    big_[static_cast<size_t>(s.a)].push_back(facet);
  }
  ++s.n;
}

void EdgeMap::erase(Slot& s, int facet) {
  if (s.n <= 2) {
    int kept[2], n = 0;
    if (s.n >= 1 && s.a != facet) kept[n++] = s.a;
    if (s.n == 2 && s.b != facet) kept[n++] = s.b;
    s.n = n;
    s.a = n >= 1 ? kept[0] : -1;
    s.b = n == 2 ? kept[1] : -1;
    return;
  }
  std::vector<int>& l = big_[static_cast<size_t>(s.a)];
  l.erase(std::remove(l.begin(), l.end(), facet), l.end());
  s.n = static_cast<int>(l.size());
  if (s.n <= 2) {
    free_big_.push_back(s.a);
    s.a = s.n >= 1 ? l[0] : -1;
    s.b = s.n == 2 ? l[1] : -1;
    l = {};
  }
}

void EdgeMap::add(int facet, const Triangle& t) {
  for (int i = 0; i < 3; ++i) push(find_or_insert(edge_key(t.v[i], t.v[(i + 1) % 3])), facet);
}

void EdgeMap::remove(int facet, const Triangle& t) {
  for (int i = 0; i < 3; ++i) {
    const size_t at = find(edge_key(t.v[i], t.v[(i + 1) % 3]));
    if (at == kNone) continue;
    erase(slots_[at], facet);
    if (slots_[at].n == 0) erase_slot(at);
  }
}

FacetList EdgeMap::facets(int a, int b) const {
  const size_t at = find(edge_key(a, b));
  return at == kNone ? FacetList{} : list(slots_[at]);
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
