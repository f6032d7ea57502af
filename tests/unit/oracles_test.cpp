// The lp and sphere oracles against the exact tetrahedralization (dt): sphere
// never says "Delaunay" wrongly; lp agrees with dt except on queries it counts
// ambiguous, and never says "Delaunay" wrongly either.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <iostream>
#include <random>
#include <set>

#include <time.h>

#include "delaunay/delaunay_tetrahedralization.h"
#include "delaunay/facet_oracle.h"
#include "geometry/point_grid.h"
#include "geometry/predicates.h"

namespace vd {
namespace {

using Triple = std::array<int, 3>;

std::vector<Vec3> cube_points(int n, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0, 1);
  std::vector<Vec3> p(static_cast<size_t>(n));
  for (Vec3& q : p) q = {u(rng), u(rng), u(rng)};
  return p;
}

// Points on the unit sphere plus points inside it: many facets on the hull,
// many with large empty spheres.
std::vector<Vec3> sphere_points(int on_sphere, int inside, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> g(0, 1);
  std::uniform_real_distribution<double> u(0, 1);
  std::vector<Vec3> p;
  for (int i = 0; i < on_sphere + inside; ++i) {
    const Vec3 d = normalized({g(rng), g(rng), g(rng)});
    p.push_back(i < on_sphere ? d : std::cbrt(u(rng)) * d);
  }
  return p;
}

Triple sorted(Triple t) {
  std::sort(t.begin(), t.end());
  return t;
}

std::vector<Triple> dt_facets(const DelaunayTetrahedralization& dt) {
  std::set<Triple> facets;
  const int n = dt.number_cells();
  for (int c = 0; c < n; ++c)
    for (int skip = 0; skip < 4; ++skip) {
      Triple f;
      int k = 0;
      for (int i = 0; i < 4; ++i)
        if (i != skip) f[static_cast<size_t>(k++)] = dt.cell(c)[static_cast<size_t>(i)];
      facets.insert(sorted(f));
    }
  return {facets.begin(), facets.end()};
}

// Triangles of a vertex and two of its nearest neighbours: most are not
// Delaunay facets, but they are the kind of facet a surface mesh holds.
std::vector<Triple> nearby_triples(const std::vector<Vec3>& points, int count, unsigned seed) {
  std::mt19937 rng(seed);
  const int n = static_cast<int>(points.size());
  std::uniform_int_distribution<int> pick(0, n - 1);
  std::uniform_int_distribution<int> rank(1, std::min(12, n - 1));
  std::vector<Triple> out;
  for (int i = 0; i < count; ++i) {
    const int v = pick(rng);
    std::vector<std::pair<double, int>> by_distance;
    for (int w = 0; w < n; ++w) {
      const Vec3 d = points[static_cast<size_t>(w)] - points[static_cast<size_t>(v)];
      by_distance.push_back({dot(d, d), w});
    }
    std::nth_element(by_distance.begin(), by_distance.begin() + 13, by_distance.end());
    std::sort(by_distance.begin(), by_distance.begin() + 13);
    const int r1 = rank(rng);
    int r2 = rank(rng);
    if (r2 == r1) r2 = r1 % std::min(12, n - 1) + 1;
    if (r2 == r1) continue;
    out.push_back(sorted({v, by_distance[static_cast<size_t>(r1)].second,
                          by_distance[static_cast<size_t>(r2)].second}));
  }
  return out;
}

// Either side first: the caller's normal is arbitrary here.
Vec3 random_normal(const std::vector<Vec3>& p, const Triple& t, std::mt19937& rng) {
  const Vec3 n = cross(p[static_cast<size_t>(t[1])] - p[static_cast<size_t>(t[0])],
                       p[static_cast<size_t>(t[2])] - p[static_cast<size_t>(t[0])]);
  return (rng() & 1) ? n : -1.0 * n;
}

struct Comparison {
  long queries = 0;
  long dt_yes = 0;
  long sphere_yes = 0;
  long sphere_wrong_yes = 0;
  long lp_agree = 0;
  long lp_wrong_yes = 0;
  long lp_unexplained_no = 0;  // dt yes, lp no, without an ambiguous count
  double seconds_dt = 0, seconds_lp = 0, seconds_sphere = 0;
};

class Oracles {
 public:
  explicit Oracles(const std::vector<Vec3>* points, const DelaunayTetrahedralization* dt,
                   int lp_limit = -1)
      : dt_(make_oracle("dt")),
        lp_(make_oracle("lp", OracleOptions{lp_limit})),
        sphere_(make_oracle("sphere")),
        points_(points) {
    for (FacetOracle* o : all()) o->attach(points, dt);
  }
  std::vector<FacetOracle*> all() { return {dt_.get(), lp_.get(), sphere_.get()}; }
  void vertex_added(int id) {
    for (FacetOracle* o : all()) o->vertex_added(id);
  }

  void compare(const std::vector<Triple>& triples, unsigned seed, Comparison& c) {
    std::mt19937 rng(seed);
    // CPU time of this thread: the build machines are shared, and wall time
    // measured other people's compilers.
    const auto now = [] {
      timespec t;
      clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
      return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
    };
    const auto seconds = [&](double t0) { return now() - t0; };
    for (const Triple& t : triples) {
      const Vec3 n = random_normal(*points_, t, rng);
      double t0 = now();
      const bool truth = dt_->is_delaunay(t[0], t[1], t[2], n);
      c.seconds_dt += seconds(t0);
      t0 = now();
      const bool by_sphere = sphere_->is_delaunay(t[0], t[1], t[2], n);
      c.seconds_sphere += seconds(t0);
      const long ambiguous_before = lp_->stats().lp_ambiguous;
      t0 = now();
      const bool by_lp = lp_->is_delaunay(t[0], t[1], t[2], n);
      c.seconds_lp += seconds(t0);
      ++c.queries;
      c.dt_yes += truth;
      c.sphere_yes += by_sphere;
      c.sphere_wrong_yes += by_sphere && !truth;
      c.lp_agree += by_lp == truth;
      c.lp_wrong_yes += by_lp && !truth;
      c.lp_unexplained_no += truth && !by_lp && lp_->stats().lp_ambiguous == ambiguous_before;
    }
  }

  const OracleStats& lp_stats() const { return lp_->stats(); }
  const OracleStats& sphere_stats() const { return sphere_->stats(); }

 private:
  std::unique_ptr<FacetOracle> dt_, lp_, sphere_;
  const std::vector<Vec3>* points_;
};

void report(const std::string& title, const Comparison& c, const OracleStats& lp,
            const OracleStats& sphere) {
  const double per_query = 1e6 / std::max<long>(c.queries, 1);
  std::cout << "[" << title << "] queries " << c.queries << ", dt Delaunay " << c.dt_yes
            << "\n  sphere: Delaunay " << c.sphere_yes << " (wrong " << c.sphere_wrong_yes << "), "
            << c.seconds_sphere * per_query << " us/query"
            << "\n  lp: agrees " << c.lp_agree << "/" << c.queries << ", wrong yes "
            << c.lp_wrong_yes << ", ambiguous " << lp.lp_ambiguous << ", " << c.seconds_lp * per_query
            << " us/query"
            << "\n      by stored apex " << lp.by_stored_apex << ", equatorial "
            << lp.by_equatorial_sphere << ", candidate apex " << lp.by_candidate_apex << ", lp "
            << lp.by_lp << ", refused " << lp.lp_refused_by_limit << "; LPs solved " << lp.lp_solved
            << ", average unknowns "
            << (lp.lp_solved ? static_cast<double>(lp.lp_unknowns) / lp.lp_solved : 0.0)
            << "\n  dt: " << c.seconds_dt * per_query << " us/query" << std::endl;
  (void)sphere;
}

void expect_consistent_stats(const OracleStats& s) {
  EXPECT_LE(s.delaunay, s.queries);
  EXPECT_LE(s.delaunay, s.by_stored_apex + s.by_equatorial_sphere + s.by_candidate_apex + s.by_lp);
  EXPECT_LE(s.by_stored_apex + s.by_equatorial_sphere + s.by_candidate_apex + s.by_lp +
                s.lp_refused_by_limit,
            s.queries);
  EXPECT_LE(s.lp_ambiguous, s.by_lp);
  EXPECT_GE(s.lp_unknowns, 4 * s.lp_solved);
}

void expect_sound(const Comparison& c) {
  EXPECT_EQ(c.sphere_wrong_yes, 0);
  EXPECT_EQ(c.lp_wrong_yes, 0);
}

void check_point_set(const std::string& title, const std::vector<Vec3>& points, unsigned seed) {
  DelaunayTetrahedralization dt;
  dt.insert(points);
  std::vector<Triple> triples = dt_facets(dt);
  const std::vector<Triple> others = nearby_triples(points, static_cast<int>(triples.size()) / 2, seed);
  triples.insert(triples.end(), others.begin(), others.end());

  Oracles oracles(&points, &dt);
  Comparison c;
  oracles.compare(triples, seed, c);
  report(title, c, oracles.lp_stats(), oracles.sphere_stats());
  const OracleStats& lp = oracles.lp_stats();
  expect_sound(c);
  EXPECT_EQ(c.lp_unexplained_no, 0);
  EXPECT_LE(lp.lp_ambiguous, c.queries / 100 + 1);
  EXPECT_GT(lp.lp_solved, 0);
  EXPECT_EQ(lp.lp_refused_by_limit, 0);
  expect_consistent_stats(lp);
  expect_consistent_stats(oracles.sphere_stats());
  // The sphere test cannot accept more than the truth, and on random points
  // it accepts a good share of it.
  EXPECT_GT(c.sphere_yes, c.dt_yes / 4);

  // Never solving an LP: still sound, every LP refused.
  Oracles no_lp(&points, &dt, 0);
  Comparison c0;
  no_lp.compare(triples, seed, c0);
  report(title + ", lp_limit 0", c0, no_lp.lp_stats(), no_lp.sphere_stats());
  expect_sound(c0);
  EXPECT_EQ(no_lp.lp_stats().lp_solved, 0);
  EXPECT_GT(no_lp.lp_stats().lp_refused_by_limit, 0);
  expect_consistent_stats(no_lp.lp_stats());

  // The paper's limit of 20 unknowns.
  Oracles limited(&points, &dt, 20);
  Comparison c20;
  limited.compare(triples, seed, c20);
  report(title + ", lp_limit 20", c20, limited.lp_stats(), limited.sphere_stats());
  expect_sound(c20);
  expect_consistent_stats(limited.lp_stats());
}

TEST(Predicates, SpheresCountTheirBoundaryAsInside) {
  const Vec3 a{0, 0, 0}, b{2, 0, 0}, c{0, 2, 0}, d{0, 0, 2};
  EXPECT_EQ(side_of_equatorial_sphere(a, b, c, {1, 1, 0}), SphereSide::inside);
  EXPECT_EQ(side_of_equatorial_sphere(a, b, c, {2, 2, 0}), SphereSide::on_boundary);
  EXPECT_EQ(side_of_equatorial_sphere(a, b, c, {1, 1, 2}), SphereSide::outside);
  EXPECT_EQ(side_of_circumsphere(a, b, c, d, {2, 2, 2}), SphereSide::on_boundary);
  EXPECT_EQ(side_of_circumsphere(a, b, c, d, {1, 1, 1}), SphereSide::inside);
  EXPECT_EQ(side_of_circumsphere(a, b, c, d, {3, 3, 3}), SphereSide::outside);
  EXPECT_EQ(orientation(a, b, c, d), 1);
  EXPECT_EQ(orientation(a, c, b, d), -1);
  EXPECT_EQ(orientation(a, b, c, {5, 5, 0}), 0);
  // Degenerate input answers "occupied", never crashes.
  EXPECT_EQ(side_of_equatorial_sphere(a, b, {4, 0, 0}, d), SphereSide::on_boundary);
  EXPECT_EQ(side_of_circumsphere(a, b, c, {5, 5, 0}, d), SphereSide::on_boundary);
}

TEST(PointGrid, BoxAndBallQueriesMatchBruteForce) {
  std::vector<Vec3> points = cube_points(500, 7);
  PointGrid grid;
  grid.build(std::vector<Vec3>(points.begin(), points.begin() + 50));
  for (int id = 50; id < 500; ++id) grid.update(id, points[static_cast<size_t>(id)]);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-0.2, 1.2);
  for (int i = 0; i < 100; ++i) {  // some moves, some far outside
    const int id = static_cast<int>(rng() % 500);
    points[static_cast<size_t>(id)] = {u(rng) * (i % 10 == 0 ? 5 : 1), u(rng), u(rng)};
    grid.update(id, points[static_cast<size_t>(id)]);
  }
  std::vector<int> got;
  for (int i = 0; i < 200; ++i) {
    const Vec3 centre{u(rng), u(rng), u(rng)};
    const double r = 0.3 * std::abs(u(rng));
    grid.in_ball(centre, r, got);
    std::sort(got.begin(), got.end());
    std::vector<int> want;
    for (int id = 0; id < 500; ++id) {
      const Vec3 d = points[static_cast<size_t>(id)] - centre;
      if (dot(d, d) <= r * r) want.push_back(id);
    }
    ASSERT_EQ(got, want);
    ASSERT_EQ(grid.any_in_ball(centre, r), !want.empty());
  }
}

// A model in a far-field box: most points in a cluster a ten-thousandth of
// the box's width, which one cell of the box's average spacing holds and
// lists in sub-cells (gmsh_simple_plane.brep's aircraft). Small queries in the
// cluster and large ones across the box find what a brute force finds,
// after appends (into the cluster and the box) and moves out of it.
TEST(PointGrid, ClusteredPointsQueriesMatchBruteForce) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  auto in_box = [&] { return Vec3{100 * unit(rng), 100 * unit(rng), 100 * unit(rng)}; };
  auto in_cluster = [&] { return Vec3{50 + 0.01 * unit(rng), 50 + 0.01 * unit(rng), 50 + 0.01 * unit(rng)}; };
  std::vector<Vec3> points;
  for (int i = 0; i < 100; ++i) points.push_back(in_box());
  for (int i = 0; i < 20000; ++i) points.push_back(in_cluster());
  PointGrid grid;
  grid.build(points);
  for (int i = 0; i < 3000; ++i) {
    points.push_back(i % 3 == 0 ? in_box() : in_cluster());
    grid.update(static_cast<int>(points.size()) - 1, points.back());
  }
  for (int i = 0; i < 50; ++i) {
    const int id = 100 + static_cast<int>(rng() % 20000);
    points[static_cast<size_t>(id)] = in_box();
    grid.update(id, points[static_cast<size_t>(id)]);
  }
  std::vector<int> got;
  for (int i = 0; i < 300; ++i) {
    const bool near = i % 2 == 0;
    const Vec3 centre = near ? in_cluster() : in_box();
    const double r = near ? 0.002 * unit(rng) : 30 * unit(rng);
    grid.in_ball(centre, r, got);
    std::sort(got.begin(), got.end());
    std::vector<int> want;
    for (int id = 0; id < static_cast<int>(points.size()); ++id) {
      const Vec3 d = points[static_cast<size_t>(id)] - centre;
      if (dot(d, d) <= r * r) want.push_back(id);
    }
    ASSERT_EQ(got, want) << "query " << i;
    ASSERT_EQ(grid.any_in_ball(centre, r), !want.empty()) << "query " << i;
    if (near) EXPECT_FALSE(got.empty() && r > 0.0015) << "query " << i;  // the cluster is dense there
  }
}

TEST(Oracles, AgreeWithTetrahedralizationInACube) {
  check_point_set("cube 300", cube_points(300, 1), 11);
  check_point_set("cube 2000", cube_points(2000, 2), 12);
}

TEST(Oracles, AgreeWithTetrahedralizationOnASphereWithInterior) {
  check_point_set("sphere 400 + 200", sphere_points(400, 200, 3), 13);
}

// Vertices added one by one, as Delaunayzation does: the
// answers follow dt, and facets found Delaunay before are confirmed by their
// stored apex.
TEST(Oracles, FollowTheGrowingVertexSet) {
  const std::vector<Vec3> all = cube_points(600, 5);
  std::vector<Vec3> points(all.begin(), all.begin() + 100);
  DelaunayTetrahedralization dt;
  dt.insert(points);
  Oracles oracles(&points, &dt);
  Comparison c;
  for (int id = 100; id < 600; ++id) {
    points.push_back(all[static_cast<size_t>(id)]);
    dt.insert_one(points.back(), id);
    oracles.vertex_added(id);
    if (id % 25 == 0) {
      std::vector<Triple> triples = dt_facets(dt);
      const auto others = nearby_triples(points, 100, static_cast<unsigned>(id));
      triples.insert(triples.end(), others.begin(), others.end());
      oracles.compare(triples, static_cast<unsigned>(id), c);
    }
  }
  report("growing 100 -> 600", c, oracles.lp_stats(), oracles.sphere_stats());
  expect_sound(c);
  EXPECT_EQ(c.lp_unexplained_no, 0);
  EXPECT_LE(oracles.lp_stats().lp_ambiguous, c.queries / 100 + 1);
  EXPECT_GT(oracles.lp_stats().by_stored_apex, 0);
  expect_consistent_stats(oracles.lp_stats());
}

// Degenerate input (a lattice: many cospherical and coplanar points,
// collinear triples) must neither crash nor loop, and "yes" stays sound.
TEST(Oracles, SurviveDegenerateInput) {
  std::vector<Vec3> points;
  for (int i = 0; i < 5; ++i)
    for (int j = 0; j < 5; ++j)
      for (int k = 0; k < 5; ++k) points.push_back({double(i), double(j), double(k)});
  DelaunayTetrahedralization dt;
  dt.insert(points);
  std::vector<Triple> triples = dt_facets(dt);
  const auto others = nearby_triples(points, 300, 9);
  triples.insert(triples.end(), others.begin(), others.end());
  triples.push_back({0, 1, 2});  // collinear
  Oracles oracles(&points, &dt);
  Comparison c;
  oracles.compare(triples, 9, c);
  report("lattice 5x5x5", c, oracles.lp_stats(), oracles.sphere_stats());
  // dt breaks ties symbolically; an empty-sphere proof with a vertex on the
  // sphere is refused, so neither oracle may claim more than dt.
  expect_sound(c);
  expect_consistent_stats(oracles.lp_stats());
}

}  // namespace
}  // namespace vd
