// The self-intersection search of surface validation splits large surfaces
// at the median box centre (two halves, then the pairs across the cut). The
// pairs it finds must not depend on where the cut falls or on the threads.
#include <gtest/gtest.h>

#include "mesh/error.h"
#include "mesh/parallel.h"
#include "mesh/shapes.h"
#include "pipeline/mesher.h"
#include "surface/validate_surface.h"

namespace vd {
namespace {

// Two overlapping unit spheres of 5,120 facets each, centres `d` apart along
// x (rotate: along y instead, by an exact quarter turn about z).
Mesh two_spheres(bool along_y) {
  Mesh m = shapes::icosphere({-0.6, 0, 0}, 1.0, 4);
  shapes::append(m, shapes::icosphere({0.6, 0, 0}, 1.0, 4));
  if (along_y)
    for (Vec3& p : m.points) p = Vec3{-p.y, p.x, p.z};
  return m;
}

TEST(SelfIntersections, SamePairsWhereverTheCutFallsAndOnAnyThreads) {
  constexpr size_t kAll = 1u << 30;
  set_thread_count(1);
  const auto side_by_side = find_self_intersections(two_spheres(false), kAll);
  set_thread_count(2);
  const auto side_by_side_2 = find_self_intersections(two_spheres(false), kAll);
  // Along y the cut at the median x runs through both spheres, along x it
  // runs between their centres, through the circle where they cross.
  const auto stacked = find_self_intersections(two_spheres(true), kAll);
  set_thread_count(0);
  ASSERT_GT(side_by_side.size(), 100u);
  EXPECT_EQ(side_by_side, side_by_side_2);
  EXPECT_EQ(side_by_side, stacked);
  for (const auto& [a, b] : side_by_side) {
    EXPECT_LT(a, 5120) << "a pair within one sphere";
    EXPECT_GE(b, 5120) << "a pair within one sphere";
  }
}

TEST(SelfIntersections, ALimitGivesTrueExamples) {
  const auto all = find_self_intersections(two_spheres(false), 1u << 30);
  const auto few = find_self_intersections(two_spheres(false), 10);
  ASSERT_EQ(few.size(), 10u);
  for (const auto& p : few) EXPECT_TRUE(std::binary_search(all.begin(), all.end(), p));
}

// In the pipeline the test runs beside the tetrahedralization and the first
// recovery when there is a second thread; a surface that crosses itself is
// still refused with the same message as on one thread, and the recovery it
// makes moot is abandoned rather than run to its guards.
TEST(SelfIntersections, ThePipelineRefusesTheSameOnOneAndTwoThreads) {
  std::string message[2];
  for (int threads : {1, 2}) {
    MeshOptions o;
    o.threads = threads;
    o.interior = false;
    try {
      mesh_surface(two_spheres(false), o);
      ADD_FAILURE() << "two crossing spheres meshed on " << threads << " thread(s)";
    } catch (const InputError& e) {
      message[threads - 1] = e.what();
    }
  }
  EXPECT_NE(message[0].find("intersects itself"), std::string::npos) << message[0];
  EXPECT_EQ(message[0], message[1]);
}

}  // namespace
}  // namespace vd
