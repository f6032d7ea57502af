// Checks a surface before meshing. Every problem is an InputError (exit 3)
// whose message names the facets (0-based indices in input order) and, where
// it helps, the vertices.
#pragma once

#include <utility>
#include <vector>

#include "mesh/mesh.h"
#include "surface/edge_map.h"

namespace vd {

struct SurfaceCheck {
  // Edges used by one facet only. Allowed for internal sheets (cracks,
  // horizons) inside a region; refused once the regions are known when a
  // facet with an open edge has the exterior on both sides.
  std::vector<std::pair<int, int>> open_edges;
  int non_manifold_edges = 0;
};

// The largest region id a facet may name: regions are numbered into arrays,
// and an id of 1e9 asked for tens of GB (1e7: 2.9 s and a report of 10
// million regions).
constexpr int kLargestRegionId = 1000000;

// Refuses (throws InputError) a facet naming a region under -1 (unknown) or
// over kLargestRegionId (-2 crashed the mesher, 2026-11-29) or a face under
// -1 (none; -3 was taken as none, and the facets got face ids of their
// own), and a vertex size that is negative or not finite (taken as none).
// Checked before anything else, validation or not.
void check_tags_and_sizes(const Mesh& surface);

// Refuses (throws InputError): no facets, vertex ids out of range, non-finite
// coordinates, degenerate facets (repeated vertex or collinear vertices),
// duplicate facets, inconsistent orientation across a manifold edge (or tags
// that contradict it), and self-intersections (exact predicates).
// `edges`, when given, is the surface's edge map (built here otherwise).
// Without `self_intersections` that test is left to the caller
// (find_self_intersections, throw_self_intersections).
SurfaceCheck validate_surface(const Mesh& surface, const EdgeMap* edges = nullptr, bool self_intersections = true);

// Only the self-intersection part: pairs of intersecting facets (at most
// `limit` of them, the smallest of those found; the same on any number of
// threads).
// `threads`: at most this many (0: thread_count()); 1 beside other work.
std::vector<std::pair<int, int>> find_self_intersections(const Mesh& surface, size_t limit = 20, int threads = 0);
// The SelfIntersectionError validate_surface throws for these pairs; nothing
// when empty.
void throw_self_intersections(const std::vector<std::pair<int, int>>& crossings);

}  // namespace vd
