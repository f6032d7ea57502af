// Independent checks of a finished mesh, used by the tests and by
// `vdmesh compare`: no inverted tetrahedra, the boundary of the tetrahedra is
// exactly the surface with its tags, and each region fills the volume its
// surface encloses.
#pragma once

#include <string>
#include <vector>

#include "mesh/mesh.h"

namespace vd {

struct ConformityReport {
  long inverted = 0;                 // tetrahedra with non-positive volume
  long faces_not_on_surface = 0;     // region-boundary faces of tetrahedra that are no surface facet
  long facets_not_on_tets = 0;       // surface facets that bound no tetrahedron as tagged
  long wrong_side_regions = 0;       // tetrahedron beside a facet with another region than the tag says
  long non_manifold_faces = 0;       // faces shared by more than two tetrahedra
  std::vector<double> region_volume;    // sum of tetrahedra, by region id
  std::vector<double> enclosed_volume;  // from the surface facets, by region id
  double max_relative_volume_error = 0;
  bool ok(double volume_tolerance = 1e-9) const {
    return inverted == 0 && faces_not_on_surface == 0 && facets_not_on_tets == 0 && wrong_side_regions == 0 &&
           non_manifold_faces == 0 && max_relative_volume_error <= volume_tolerance;
  }
  std::string summary() const;
};

ConformityReport check_conformity(const Mesh& mesh);

// Tetrahedra whose corners turn the wrong way (exact orientation < 0), and
// turning them (two corners swapped, their mid-edge nodes with them). A
// mesh of another program's convention has all of them so: FreeCAD's
// FemMesh.write(".vtu") writes every tetrahedron inverted, and `vdmesh
// convert --reorient` makes such a mesh usable. Flat ones stay as they are.
long count_turned_tetrahedra(const Mesh& mesh);
long turn_inverted_tetrahedra(Mesh& mesh);

}  // namespace vd
