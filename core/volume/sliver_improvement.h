// Sliver removal, cases B and C of paper §7 (see volume/sliver_removal.h).
//
// Every change replaces the tetrahedra of a star-shaped cavity by others with
// the same boundary, and is kept only when each new tetrahedron is positive
// by the exact orientation predicate: positive tetrahedra whose boundary is
// the cavity's tile it exactly once, so the mesh stays valid and conforming.
// Surface facets are never flipped. A surface vertex moves only inside a flat
// patch (all its facets in one plane, one face id: SlidePlane), in that plane,
// or along a straight crease between two flat faces, so the surface's shape
// stays as case A left it.
// A vertex move also keeps every surface facet a face of the Delaunay
// tetrahedralization of the vertices: each facet keeps the range of its empty
// spheres, first read from the Delaunay tetrahedra on its two sides, and a
// vertex may only move where that range stays open (FacetWitnesses).
#pragma once

#include "mesh/mesh.h"
#include "volume/sliver_removal.h"

namespace vd {

// Runs up to options.max_passes passes over the tetrahedra under the sliver
// angle, worst first: the best improving flip (case B) if there is one, else
// the best improving move of one of the sliver's interior vertices (case C).
// Deterministic: no random choice, the order is by quality then index.
// `apexes` gives, for each surface facet of m, the vertices opposite it in
// the Delaunay tetrahedralization of m.points (FacetApexes); every facet must
// be a face of it, as after the pipeline's recovery and case A.
// `apexes_done` (may be empty) is called as soon as `apexes` is no longer
// needed, before the passes: the caller may free what answers it.
// `measures`: each tetrahedron's smallest_dihedral_if_positive when the
// caller has them (one per tetrahedron of m), else empty.
void improve_slivers(Mesh& m, const SliverOptions& options, const FacetApexes& apexes, SliverStats& stats,
                     const std::function<void()>& apexes_done = {}, std::vector<double> measures = {});

}  // namespace vd
