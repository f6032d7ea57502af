// VolumeKeeper: the volume change it books for a split vertex off the chord
// and for a flip is the change of the regions' enclosed volumes, and it
// refuses only the moves that take a region farther past its limit.
#include <gtest/gtest.h>

#include <array>
#include <optional>

#include "surface/edge_map.h"
#include "surface/volume_keeper.h"
#include "test_support.h"
#include "volume/region_tetrahedra.h"

namespace vd {
namespace {

struct Edge {
  int p, q;
  std::vector<int> sharing;
};

// An edge whose facets all have their vertices in the plane `coordinate`
// (0: x, 1: y, 2: z) = `value`.
Edge edge_in_plane(const Mesh& m, int coordinate, double value) {
  const EdgeMap edges(m.triangles);
  auto in_plane = [&](int v) { return std::abs(m.points[v][coordinate] - value) < 1e-12; };
  for (size_t f = 0; f < m.triangles.size(); ++f)
    for (int i = 0; i < 3; ++i) {
      const int p = m.triangles[f].v[i], q = m.triangles[f].v[(i + 1) % 3];
      const auto& list = edges.facets(p, q);
      std::vector<int> sharing(list.begin(), list.end());
      bool flat = sharing.size() >= 2;
      for (int g : sharing)
        for (int v : m.triangles[g].v) flat = flat && in_plane(v);
      if (flat) return {p, q, sharing};
    }
  ADD_FAILURE() << "no edge in the plane";
  return {};
}

// The split the Delaunayzer makes, with the new vertex at `point`.
Mesh split(Mesh m, const Edge& e, const Vec3& point) {
  const int v = static_cast<int>(m.points.size());
  m.points.push_back(point);
  for (int f : e.sharing) {
    const Triangle t = m.triangles[f];
    const int a = has_directed_edge(t, e.p, e.q) ? e.p : e.q, b = a == e.p ? e.q : e.p;
    const int c = opposite_vertex(t, e.p, e.q);
    Triangle first = t, second = t;
    first.v = {a, v, c};
    second.v = {v, b, c};
    m.triangles[f] = first;
    m.triangles.push_back(second);
  }
  return m;
}

Vec3 middle(const Mesh& m, const Edge& e) { return 0.5 * (m.points[e.p] + m.points[e.q]); }

TEST(VolumeKeeper, BooksASplitAsTheEnclosedVolumesChange) {
  const Mesh m = test::two_boxes_sharing_a_face(2);
  // The interface x = 1: a point pushed into region 2 moves volume from 2 to 1.
  const Edge e = edge_in_plane(m, 0, 1.0);
  ASSERT_EQ(e.sharing.size(), 2u);
  VolumeKeeper keeper(m, {0.0, 1.0, 1.0}, 0.5);
  const Vec3 point = middle(m, e) + Vec3{0.05, 0, 0};
  ASSERT_TRUE(keeper.take_split(m, e.p, e.q, e.sharing, point));
  const std::vector<double> after = enclosed_volumes(split(m, e, point));
  EXPECT_GT(after[1], 1.0);
  EXPECT_NEAR(keeper.error(1), after[1] - 1.0, 1e-12);
  EXPECT_NEAR(keeper.error(2), after[2] - 1.0, 1e-12);
  EXPECT_NEAR(keeper.error(1), -keeper.error(2), 1e-12);
}

TEST(VolumeKeeper, RefusesOnlyWhatTakesARegionFartherPastTheLimit) {
  const Mesh m = test::two_boxes_sharing_a_face(2);
  const Edge e = edge_in_plane(m, 0, 0.0);  // region 1 against the exterior
  ASSERT_EQ(e.sharing.size(), 2u);
  const Vec3 c = middle(m, e);
  // Pushed out by d, region 1 gains d/3 times the area of the two facets.
  // The n = 2 box's facets have area 1/8: 0.01 gains 1/1200, 0.083 %.
  VolumeKeeper keeper(m, {0.0, 1.0, 1.0}, 0.004);
  EXPECT_TRUE(keeper.take_split(m, e.p, e.q, e.sharing, c + Vec3{-0.01, 0, 0}));
  EXPECT_NEAR(keeper.error(1), 0.01 / 12, 1e-12);
  // 0.1 more would end at 0.92 %, past 0.4 %: refused, nothing booked.
  EXPECT_FALSE(keeper.take_split(m, e.p, e.q, e.sharing, c + Vec3{-0.1, 0, 0}));
  EXPECT_NEAR(keeper.error(1), 0.01 / 12, 1e-12);
  // Judged by the two facets' change together: 0.06 out adds 0.25 % by each
  // facet, 0.5 % in all, which would end past 0.4 %.
  EXPECT_FALSE(keeper.take_split(m, e.p, e.q, e.sharing, c + Vec3{-0.06, 0, 0}));
  EXPECT_NEAR(keeper.error(1), 0.01 / 12, 1e-12);

  // A region already past the limit (1 % over): a move back toward its
  // volume passes, one that adds to it does not, however small.
  VolumeKeeper over(m, {0.0, 1.0 / 1.01, 1.0}, 0.004);
  EXPECT_FALSE(over.take_split(m, e.p, e.q, e.sharing, c + Vec3{-1e-4, 0, 0}));
  EXPECT_TRUE(over.take_split(m, e.p, e.q, e.sharing, c + Vec3{0.01, 0, 0}));
  EXPECT_LT(over.error(1), 0.01);
}

TEST(VolumeKeeper, BooksAFlipAsTheEnclosedVolumeChanges) {
  Mesh m = test::two_boxes_sharing_a_face(2);
  const Edge e = edge_in_plane(m, 0, 0.0);
  ASSERT_EQ(e.sharing.size(), 2u);
  // Lift one opposite corner off the face so the flip changes the volume.
  Triangle t = m.triangles[e.sharing[0]], t2 = m.triangles[e.sharing[1]];
  if (!has_directed_edge(t, e.p, e.q)) std::swap(t, t2);
  const int r = opposite_vertex(t, e.p, e.q), s = opposite_vertex(t2, e.p, e.q);
  m.points[r].x -= 0.02;
  VolumeKeeper keeper(m, {0.0, 1.0, 1.0}, 0.5);
  const double before = enclosed_volumes(m)[1];
  Triangle a = t, b = t;
  a.v = {s, e.q, r};
  b.v = {r, e.p, s};
  keeper.record_flip(m, t, t2, a, b);
  m.triangles[e.sharing[0]] = a;
  m.triangles[e.sharing[1]] = b;
  const double after = enclosed_volumes(m)[1];
  EXPECT_GT(std::abs(after - before), 1e-4);
  EXPECT_NEAR(keeper.error(1), after - 1.0, 1e-12);
}

}  // namespace
}  // namespace vd
