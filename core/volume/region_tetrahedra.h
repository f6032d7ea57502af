// The tetrahedra of each region (paper §6): the Delaunay tetrahedra of the
// final vertex set, grouped into regions by the recovered surface. Tetrahedra
// connected without crossing a surface facet form one region; the component
// touching infinity is region 0 (the exterior) and is dropped.
#pragma once

#include "mesh/mesh.h"

namespace vd {

class DelaunayTetrahedralization;

struct RegionStats {
  int regions = 0;            // non-zero regions
  int tets_in_exterior = 0;   // dropped
  bool regions_from_tags = false;
  // The regions of the last build were kept and the tetrahedra that new
  // interior vertices made took their vertex's region (core/pipeline/mesher.cpp).
  bool labelled_by_new_vertices = false;
};

// Pre: every facet of surface.triangles is a face of dt. Fills surface.tets
// (regions > 0 only). When the facets carry region tags, they are checked
// against the components (FacetsError on a contradiction); otherwise regions
// are numbered 1.. by their lowest bounding facet and the facets' front/back
// are set. Facets with the exterior on both sides are refused (FacetsError:
// an open surface that bounds nothing). Leaves each tetrahedron of dt
// labelled with its region (0 for the exterior; see label_cells).
RegionStats build_region_tetrahedra(Mesh& surface, DelaunayTetrahedralization& dt);

// Where the regions were found from the surface (no region tags), after
// build_region_tetrahedra: the regions holding m.region_points take their
// ids (a hole's region becomes exterior, winning over region points; of two
// region points in one region the last wins, as in TetGen), the others are
// numbered after the largest id given. The facets' sides follow, and the
// facets left with the exterior on both sides (between a hole and the
// exterior, or two holes) are dropped. Returns true when anything changed:
// the tetrahedra must then be built again.
bool apply_region_points(Mesh& surface, const DelaunayTetrahedralization& dt);

// Signed volume of tetrahedron (a, b, c, d): positive when positively oriented.
double tet_volume(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d);
// Volume enclosed by the surface for each region (index = region id), from
// the facets' front/back tags (divergence theorem).
std::vector<double> enclosed_volumes(const Mesh& surface);
// Sum of tetrahedron volumes per region.
std::vector<double> region_volumes(const Mesh& mesh);

}  // namespace vd
