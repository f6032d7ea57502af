// What keeps each surface facet a Delaunay face while vertices move (the
// sliver pass's case C).
//
// The spheres through a facet's three vertices form a pencil, one sphere per
// position s of the centre along the facet's normal; the facet is Delaunay
// while some sphere of the pencil has every other vertex strictly outside. A
// vertex above the facet's plane is outside the spheres with s below some
// value, one below it outside those with s above some value, so the empty
// spheres are an interval (L, U): U set by the vertex above that allows the
// least, L by the one below. The two Delaunay tetrahedra beside the facet give
// both at the start: their apexes are those vertices (a side on the convex
// hull has no bound). A vertex may go to p when the interval stays open (p
// above: the vertex giving L is outside the sphere through the facet and p),
// and the bound tightens when p allows less than the vertex that gave it. A
// bound keeps the position of a vertex that moved away: the true interval is
// then only wider. Every decision is an exact predicate on points: the bounds
// are kept as points.
#pragma once

#include <array>
#include <cstdint>
#include <unordered_map>
#include <vector>

#include "geometry/point_grid.h"
#include "geometry/predicates.h"
#include "mesh/mesh.h"
#include "volume/sliver_removal.h"

namespace vd {

class FacetWitnesses {
 public:
  // `points` is read as it changes (it must outlive this); `apexes[k]`: the
  // apexes of triangle k's two tetrahedra in the Delaunay tetrahedralization
  // (FacetApexes), -1 on the hull, -2 for a triangle that is not a face of it
  // (std::logic_error). Given as a list, not the function: the
  // tetrahedralization can go before these are built.
  FacetWitnesses(const std::vector<Vec3>& points, const std::vector<Triangle>& triangles,
                 const std::vector<std::array<int, 2>>& apexes);

  // True when every surface facet stays Delaunay with vertex `moving` at p.
  // The facets of a moving surface vertex change shape:
  // reshape_allows decides for them.
  bool allows(const Vec3& p, int moving) const;
  // With surface vertex v at p, is each of its facets Delaunay: with an
  // empty equatorial sphere, or with every vertex in that sphere on one side
  // and a sphere of its pencil leaning to the other side empty
  // (reshaped_bounds)?
  bool reshape_allows(int v, const Vec3& p);
  // Vertex v moved to p (allowed, a surface vertex by reshape_allows, else
  // std::logic_error; `points` already says so): the bounds p tightens take
  // it, and the facets of a surface vertex get the bounds reshape_allows
  // found.
  void moved(int v, const Vec3& p);
  // Facets looked at so far by allows and the bounds' updates (a measure of
  // the work, for budgets that must not depend on the clock).
  long tests_made() const { return tests_made_; }

 private:
  // A bound of a facet's interval: none (a convex-hull side: no vertex
  // beyond the facet's plane, which every move keeps, since none leaves
  // the tetrahedra), a vertex position, or the equatorial sphere itself
  // (s = 0, for facets that changed shape: the interval reaches 0, held or
  // not).
  struct Bound {
    enum Kind { none, point, equatorial } kind = none;
    Vec3 at;
  };
  struct HalfSpace {
    Vec3 origin, normal;  // the facet's circumcentre; towards the ball's centre
    double lens = 0;      // how far behind the plane the ball may reach
    double radius = 0;    // the facet's circumradius, with a margin
    bool centre_on_bound_side = true;  // the usual case: the bound vertex is outside the circumcircle
  };
  struct Facet {
    std::array<int, 3> v;
    Bound above, below;
    // Every pencil sphere between the two bounds lies in the union of
    // theirs, so these two balls (approximate, with a margin) hold every
    // point the facet's tests could refuse or tighten on, now and later.
    Ball reach[2];
    // A ball far larger than the facet (a bound nearly in its plane, such as
    // a vertex outside a flat face, 1e-22 off its plane after the random
    // shift) is tested as what it is near the facet: the side of the facet's
    // plane it lies on, less the thin lens it reaches across. Its own test,
    // on squared distances of 1e35 with a relative margin, took every point
    // near the part for near: on a thin plate the exact tests that followed
    // and the walk through the list of such facets were 85 % of a 130 s
    // sliver pass. The side and the lens come from exact predicates and
    // bounds, not from the ball, whose centre is noise at that flatness.
    // Index into halves_ per side, -1 when the side is a ball: few facets
    // have one, and in the facet it doubled its size.
    int half[2] = {-1, -1};
    int face = 0;
  };
  // The half-space balls of the facets of one face and one side, looked at
  // together: a point well behind the plane of all of them skips the lot.
  // Bounds only widen, so members that changed stay covered.
  struct HalfSpaceGroup {
    Vec3 normal;                 // the first member's
    double nearest_offset = 0;   // smallest (origin . normal) over the members
    double largest_lens = 0;
    double tilt = 0;             // largest |member normal - normal|
    double farthest_origin = 0;  // largest |origin|
    double largest_radius = 0;   // of the members' circumcircles
    std::vector<int> members;    // facet ids
  };
  using Cell = std::array<std::int64_t, 3>;
  struct CellHash {
    size_t operator()(const Cell& k) const {
      return (size_t(k[0]) * 73856093u) ^ (size_t(k[1]) * 19349663u) ^ (size_t(k[2]) * 83492791u);
    }
  };

  Cell cell_of(const Vec3& p, int level) const;
  void narrow_to_equatorial(Facet& f) const;
  // What a point is looked up for: allows tests it against the bound on the
  // other side of the facet, tighten against the one on its own side.
  enum class Lookup { allows, tightens };
  template <class Visit>
  void for_each_near(const Vec3& p, Lookup lookup, Visit visit);
  void tighten(const Vec3& p, int moving);
  void spread(int id);
  // The bounds of facet `id` at the positions in grid_ (its vertex moved
  // there; `on_hull`: in the axis plane of a hull facet), or false when no
  // sphere of its pencil is known empty. `occupants`: scratch.
  bool reshaped_bounds(int id, bool on_hull, std::vector<int>& occupants, Bound& above, Bound& below) const;
  static bool point_past(const Vec3& a, const Vec3& b, const Vec3& c, const Bound& held, int side, Bound& past);
  bool open_side_bound(const Vec3& a, const Vec3& b, const Vec3& c, const std::array<int, 3>& v, const Bound& held,
                       int open_side, std::vector<int>& scratch, Bound& open) const;
  // By v's facets (facets_of_ order): which stay on the hull when v moves
  // from `from` to p.
  std::vector<char> on_hull_planes(int v, const Vec3& from, const Vec3& p) const;

  const std::vector<Vec3>& points_;
  PointGrid grid_;  // the current positions, for the reshaped facets' spheres
  bool grid_built_ = false;
  double cell_ = 1.0;
  std::vector<Facet> facets_;
  std::vector<HalfSpace> halves_;
  std::vector<std::vector<int>> facets_of_;  // per vertex
  // A facet's balls are listed in the cells they cover at the first level
  // whose cells are larger than their radius (kFitCells); level k's cells are
  // kLevelScale[k] times cell_ (twice the mean edge). Larger (or flat,
  // infinite) ones are in large_ and looked at for every point. The levels
  // under the mean edge are for surfaces whose facets differ in size by
  // orders: gmsh_simple_plane.brep's nose and wing tips put 26,280 facets in
  // one cell of the mean edge, and its sliver pass looked at 178 million
  // listed facets (4,600 a query) to find 1 million whose balls held the
  // point. With these levels and balls under one cell (they were under three
  // cells, from the mean edge's level up): 42 million looked at and 2.3
  // million listings made instead of 8 (the lever 122 -> 42 million,
  // Nefertiti's volume run 71 -> 96 million looked at but 7.1 -> 2.1 million
  // listings); balls under half a cell or under 1.5 cells did worse.
  static constexpr int kLevels = 10;
  static constexpr std::array<double, kLevels> kLevelScale = {1.0 / 64, 1.0 / 16, 1.0 / 4, 1, 4, 16, 64, 256, 1024, 4096};
  static constexpr double kFitCells = 1.0;
  std::vector<int> large_;
  // Groups of half-space sides whose centre is on their bound's side (only
  // tighten needs them; allows finds them in the cells, by their lens) and
  // of the others (both need them).
  std::vector<HalfSpaceGroup> groups_[2];
  std::unordered_map<std::int64_t, int> group_of_[2];  // (face, side, normal) -> groups_ index
  // `circle`: the facet's equatorial sphere.
  bool fill_half_space(Facet& f, int i, const Bound& bound, const Ball& circle);
  void join_group(int id, int i);
  long tests_made_ = 0;
  std::vector<char> in_large_;  // per facet
  std::vector<char> grouped_;   // per facet and side: in its group's members
  std::array<std::unordered_map<Cell, std::vector<int>, CellHash>, kLevels> cells_;
};

}  // namespace vd
