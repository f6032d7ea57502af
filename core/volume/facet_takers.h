// Which points would take a surface facet out of the Delaunay
// tetrahedralization, were they inserted into it alone: the cautious run's
// test of interior candidates (pipeline/mesher.cpp). A facet goes when the
// point lies inside the circumspheres of both tetrahedra beside it (both are
// in its cavity); the exact test with CGAL's symbolic perturbation
// (perturbed_side_of_circumsphere) agrees with the tetrahedralization's own
// conflict zone, and costs two in-sphere tests per facet whose smaller ball
// meets the point's grid cell instead of a conflict-zone walk per point
// (gmsh_simple_plane.brep's cautious run: 16 s with the walk).
#pragma once

#include <array>
#include <cstdint>
#include <unordered_map>
#include <vector>

#include "delaunay/delaunay_tetrahedralization.h"
#include "mesh/mesh.h"

namespace vd {

class FacetTakers {
 public:
  // The facets of m that are faces of dt now, with the apexes beside them.
  // Facets on the convex hull are left out: a point inside the model cannot
  // take them.
  FacetTakers(const Mesh& m, const DelaunayTetrahedralization& dt);
  // Would p, inserted alone, take one of them out?
  bool takes_a_facet(const Vec3& p) const;

 private:
  struct Facet {
    std::array<int, 3> v;  // (v0, v1, v2, apex[0]) and (v0, v2, v1, apex[1]) positive
    std::array<int, 2> apex;
  };
  bool takes(const Facet& f, const Vec3& p) const;

  const std::vector<Vec3>& points_;
  std::vector<Facet> facets_;
  // Grids of cells 4^level times the finest; a facet is listed on the
  // finest level whose cells are as wide as its smaller ball, in the (at
  // most 8) cells the ball meets, so no ball is listed in many cells.
  double finest_ = 1;
  std::vector<std::unordered_map<std::uint64_t, std::vector<int>>> levels_;
  std::vector<int> everywhere_;  // facets whose ball is not finite
};

}  // namespace vd
