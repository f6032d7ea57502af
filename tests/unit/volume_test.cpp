// Interior vertices and the tetrahedra per region (paper §2, §6).
#include <gtest/gtest.h>

#include <cmath>
#include <iostream>

#include "mesh/shapes.h"
#include "pipeline/mesher.h"
#include "quality/conformity.h"
#include "volume/interior_vertices.h"

namespace vd {
namespace {

MeshResult mesh_with_interior(const Mesh& in, double size = 0) {
  MeshOptions o;
  o.size.uniform = size;
  return mesh_surface(in, o);
}

TEST(Volume, UniformSizeFillsACubeWithALattice) {
  const Mesh in = shapes::box({0, 0, 0}, {1, 1, 1}, 8);
  const MeshResult r = mesh_with_interior(in, 0.125);
  const ConformityReport c = check_conformity(r.mesh);
  EXPECT_TRUE(c.ok()) << c.summary();
  EXPECT_NEAR(c.region_volume[1], 1.0, 1e-9);
  // FCC spacing h in a unit cube: about sqrt(2)/h^3 points; the near-surface
  // band is left to the offset points.
  EXPECT_GT(r.report.interior_vertices, 500);
  EXPECT_GT(r.report.quality.min_dihedral_deg, 0.0);
  std::cout << "[cube h=1/8] " << r.report.interior_vertices << " interior vertices, " << r.mesh.tets.size()
            << " tets, min dihedral " << r.report.quality.min_dihedral_deg << ", under 10 deg "
            << r.report.quality.below_10_deg << ", surface vertices added " << r.report.added_surface_vertices
            << "\n";
}

TEST(Volume, InterfaceBetweenTwoRegionsWithInteriorVertices) {
  Mesh in = shapes::box({0, 0, 0}, {1, 1, 1}, 4, 1, 1);
  shapes::append(in, shapes::box({1, 0, 0}, {2, 1, 1}, 4, 2, 7));
  shapes::weld_exact(in);
  shapes::merge_coincident_facets(in);
  const MeshResult r = mesh_with_interior(in);
  const ConformityReport c = check_conformity(r.mesh);
  EXPECT_TRUE(c.ok()) << c.summary();
  EXPECT_NEAR(c.region_volume[1], 1.0, 1e-9);
  EXPECT_NEAR(c.region_volume[2], 1.0, 1e-9);
  EXPECT_GT(r.report.interior_vertices, 0);
  ASSERT_EQ(r.report.tets_per_region.size(), 3u);
  EXPECT_GT(r.report.tets_per_region[1], 0);
  EXPECT_GT(r.report.tets_per_region[2], 0);
}

TEST(Volume, NoInteriorPointOutsideTheSolid) {
  // A box with a hole: the hole and the outside get no interior vertices.
  const Mesh in = shapes::box_with_hole({0, 0, 0}, {4, 4, 1}, 0.5);
  const MeshResult r = mesh_with_interior(in, 0.25);
  EXPECT_TRUE(check_conformity(r.mesh).ok());
  // Added vertices (interior ones, and surface ones on the walls) stay in the
  // closed solid.
  const double eps = 1e-9;
  for (size_t v = in.points.size(); v < r.mesh.points.size(); ++v) {
    const Vec3& p = r.mesh.points[v];
    const bool in_hole = std::abs(p.x - 2) < 1 - eps && std::abs(p.y - 2) < 1 - eps;
    EXPECT_FALSE(in_hole) << "vertex " << v << " in the hole";
    EXPECT_TRUE(p.x > -eps && p.x < 4 + eps && p.y > -eps && p.y < 4 + eps && p.z > -eps && p.z < 1 + eps)
        << "vertex " << v << " outside";
  }
}

TEST(Volume, SameSeedSameMeshWithInteriorVertices) {
  const Mesh in = shapes::icosphere({0, 0, 0}, 1.0, 2);
  const MeshResult a = mesh_with_interior(in), b = mesh_with_interior(in);
  ASSERT_EQ(a.mesh.tets.size(), b.mesh.tets.size());
  for (size_t i = 0; i < a.mesh.tets.size(); ++i) ASSERT_EQ(a.mesh.tets[i].v, b.mesh.tets[i].v);
  for (size_t i = 0; i < a.mesh.points.size(); ++i) ASSERT_EQ(a.mesh.points[i].z, b.mesh.points[i].z);
}

TEST(Volume, PointTriangleDistance) {
  const Vec3 a{0, 0, 0}, b{1, 0, 0}, c{0, 1, 0};
  EXPECT_DOUBLE_EQ(point_triangle_distance({0.2, 0.2, 3}, a, b, c), 3.0);   // above the inside
  EXPECT_DOUBLE_EQ(point_triangle_distance({-1, 0, 0}, a, b, c), 1.0);      // beyond vertex a
  EXPECT_DOUBLE_EQ(point_triangle_distance({0.5, -2, 0}, a, b, c), 2.0);    // beyond edge ab
  EXPECT_NEAR(point_triangle_distance({1, 1, 0}, a, b, c), std::sqrt(0.5), 1e-15);  // beyond edge bc
}

}  // namespace
}  // namespace vd
