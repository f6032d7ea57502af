// Second-order (10-node) tetrahedra: one node per mesh edge, shared by every
// tetrahedron and boundary triangle on that edge (`--order 2`).
//
// On CAD input the nodes of surface edges go onto the CAD face, or onto the
// CAD edge between two faces, so that the elements follow the true geometry.
// A curved node is put back on the chord where it would make an element's
// Jacobian fold over (or come close to it): a solver cannot use such an
// element, and a straight one is still second order.
#pragma once

#include <array>

#include "mesh/mesh.h"

namespace vd {

class SurfaceGeometry;

struct SecondOrderStats {
  long nodes = 0;            // mid-edge nodes added
  long surface_nodes = 0;    // of which on surface edges
  long on_geometry = 0;      // surface nodes moved off the chord onto the geometry
  long kept_straight = 0;    // surface nodes put back on the chord for a valid Jacobian
  double min_scaled_jacobian = 1;  // smallest det J / det J(straight) over the checked points
};

// Adds the mid-edge nodes (Mesh::tet_mid, Mesh::triangle_mid) to a linear
// mesh. `geometry` may be null: the nodes stay at the edge mid-points.
SecondOrderStats make_second_order(Mesh& m, const SurfaceGeometry* geometry = nullptr);

// Drops the mid-edge nodes, and the points only they used.
void make_first_order(Mesh& m);

// det J of the quadratic map from the reference tetrahedron (corners x[0..3],
// mid-edge nodes x[4..9] in Mesh::TetMidNodes order) at barycentric point l.
double quadratic_tet_jacobian(const std::array<Vec3, 10>& x, const std::array<double, 4>& l);

// Volume of a quadratic tetrahedron (exact: det J is a cubic, integrated by a
// degree-3 rule).
double quadratic_tet_volume(const std::array<Vec3, 10>& x);

// Area of a quadratic triangle (corners x[0..2], mid-edge nodes x[3..5]);
// a degree-5 rule, so exact for flat triangles and close for curved ones.
double quadratic_triangle_area(const std::array<Vec3, 6>& x);

// The ten nodes of tetrahedron `t` of a second order mesh.
std::array<Vec3, 10> tet_nodes(const Mesh& m, size_t t);

}  // namespace vd
