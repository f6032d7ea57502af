// Helpers shared by the unit tests: where the shared data is, temp files.
#pragma once

#include <gtest/gtest.h>

#include <string>

#include "mesh/mesh.h"

namespace vd::test {

// Folder of the shared geometry: $VDMESH_DATA, else ../shared/data beside the
// source tree.
std::string data_dir();
// Full path of a shared file, or "" when it is not there.
std::string data_file(const std::string& relative);
// A fresh path under the build's temp folder.
std::string temp_path(const std::string& name);

// Two-region shapes of the paper's cases: unit boxes [0,1]^3 (region 1,
// faces 1-6) and [1,2]x[0,1]^2 (region 2, faces 7-12), each side n x n,
// sharing one interface face; and the box [1,2]^3 (region 2, sides 2 x 2)
// nested in [0,3]^3 (region 1, sides 3 x 3).
Mesh two_boxes_sharing_a_face(int n);
Mesh box_in_box();
// A wedge (region 1) of a 1 x 1 base and a top rising from the edge x = 0
// to height sin(deg) at x = 1: its edge at x = 0 is a dihedral angle of
// about deg degrees.
Mesh thin_wedge(double deg);

// Facets of m that are not faces of a Delaunay tetrahedralization built
// afresh from m's points (not the one the mesher kept): 0 when the surface
// is recovered.
int facets_missing_from_fresh_dt(const Mesh& m);

}  // namespace vd::test

// Skips the current test, naming the missing file, when the shared data is
// not there (a clone without ../shared). CI always has it.
#define VD_REQUIRE_DATA(var, rel)                                                  \
  const std::string var = ::vd::test::data_file(rel);                              \
  if (var.empty()) GTEST_SKIP() << "shared data not found: " << ::vd::test::data_dir() \
                                << "/" << (rel) << " (set VDMESH_DATA)"
