#include "volume/facet_witnesses.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace vd {
namespace {

bool has(const std::array<int, 3>& f, int v) { return f[0] == v || f[1] == v || f[2] == v; }

// A reshaped facet's bounds (reshaped_bounds) at most this many times the
// facet's circumradius.
constexpr double kLargestHeldBall = 8.0;
// How far from a bound's sphere's centre point_past goes, in its radii. At
// 1.05 the narrowed bounds held a cylindrical shell's pass at 9.77 deg and a
// cone shell's at 14.41 (19.19 and 20.0 from 1.5 up); gmsh_t20_component8.step
// came out at 9.16, 5.62, 7.97 and 13.07 deg at 1.05, 1.5, 2 and 3 (and 4).
constexpr double kPastReach = 3.0;

}  // namespace

FacetWitnesses::FacetWitnesses(const std::vector<Vec3>& points, const std::vector<Triangle>& triangles,
                               const std::vector<std::array<int, 2>>& apexes_of)
    : points_(points), facets_of_(points.size()), in_large_(triangles.size(), 0), grouped_(2 * triangles.size(), 0) {
  double edge_sum = 0;
  for (const Triangle& t : triangles)
    for (int e = 0; e < 3; ++e) edge_sum += norm(points[t.v[(e + 1) % 3]] - points[t.v[e]]);
  cell_ = triangles.empty() ? 1.0 : 2.0 * edge_sum / (3.0 * triangles.size());
  facets_.reserve(triangles.size());
  if (apexes_of.size() != triangles.size()) throw std::logic_error("facet witnesses: apexes of other triangles");
  for (size_t k = 0; k < triangles.size(); ++k) {
    const Triangle& t = triangles[k];
    const std::array<int, 2>& apex = apexes_of[k];
    if (apex[0] == -2) throw std::logic_error("facet witnesses: a surface facet is not a Delaunay face");
    Facet f;
    f.v = t.v;
    f.face = t.face;
    for (int x : apex) {
      if (x < 0) continue;
      const int side = orientation(points[t.v[0]], points[t.v[1]], points[t.v[2]], points[x]);
      Bound& b = side > 0 ? f.above : f.below;
      if (side == 0 || b.kind != Bound::none)
        throw std::logic_error("facet witnesses: a facet's Delaunay apexes are not on two sides");
      b = {Bound::point, points[x]};
    }
    narrow_to_equatorial(f);
    for (int x : t.v) facets_of_[x].push_back(static_cast<int>(facets_.size()));
    facets_.push_back(f);
    spread(static_cast<int>(facets_.size()) - 1);
  }
}

namespace {

// p (off the plane) leaves the interval open against the bound on the other side.
template <class Bound>
bool outside_bound(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& p, const Bound& other) {
  switch (other.kind) {
    case Bound::none: return true;
    case Bound::point: return side_of_circumsphere(a, b, c, p, other.at) == SphereSide::outside;
    case Bound::equatorial: return side_of_equatorial_sphere(a, b, c, p) == SphereSide::outside;
  }
  return false;
}

// p, on the side of `same`, allows less than it.
template <class Bound>
bool tightens(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& p, const Bound& same) {
  switch (same.kind) {
    case Bound::none: return true;
    case Bound::point: return side_of_circumsphere(a, b, c, p, same.at) == SphereSide::outside;
    case Bound::equatorial: return side_of_equatorial_sphere(a, b, c, p) == SphereSide::inside;
  }
  return false;
}

}  // namespace

// An apex far from the facet (across a concave part of the exterior, or a
// flat tetrahedron) makes a ball that spans the model, and every candidate
// position was tested against it: a thousand such facets made the sliver pass
// of gmsh_ellipses.brep twice as slow. A bound may be replaced by any sphere
// of the pencil between it and the other bound (the interval only narrows),
// and the equatorial sphere (s = 0) is the smallest: taken when it lies in
// the interval, i.e. when the apex on the other side is strictly outside it
// and this one not inside it.
void FacetWitnesses::narrow_to_equatorial(Facet& f) const {
  const Vec3 &a = points_[f.v[0]], &b = points_[f.v[1]], &c = points_[f.v[2]];
  auto large = [&](const Bound& x) {
    return x.kind == Bound::point && !(circumsphere(a, b, c, x.at).radius < 3.0 * cell_);
  };
  auto equatorial_side = [&](const Bound& x) {
    return x.kind == Bound::none ? SphereSide::outside : side_of_equatorial_sphere(a, b, c, x.at);
  };
  const SphereSide above = equatorial_side(f.above), below = equatorial_side(f.below);
  const bool narrow_above = large(f.above) && above != SphereSide::inside && below == SphereSide::outside;
  const bool narrow_below = large(f.below) && below != SphereSide::inside && above == SphereSide::outside;
  if (narrow_above) f.above = {Bound::equatorial, Vec3{}};
  if (narrow_below) f.below = {Bound::equatorial, Vec3{}};
  // Else a point past the other bound's sphere (point_past), when it lies
  // between the two: on a spherical shell 0.5 thick, the facets inside it had the
  // hollow's far side as their apex there, and the other apex, across the
  // wall, in their equatorial sphere; each of these balls, as large as the
  // hollow, was looked at for every move in it (234 million tests, 5 s).
  for (Bound* big : {&f.above, &f.below}) {
    const Bound& other = big == &f.above ? f.below : f.above;
    if (!large(*big) || other.kind == Bound::none) continue;
    Bound past;
    if (point_past(a, b, c, other, orientation(a, b, c, big->at), past) && tightens(a, b, c, past.at, *big))
      *big = past;
  }
}

// A point on the given side of facet (a, b, c), kPastReach radii from the
// centre of the sphere of bound `held` (on the other side): a bound for that
// side between held's and the spheres that lean farther. False when
// rounding puts it elsewhere or it overflows.
bool FacetWitnesses::point_past(const Vec3& a, const Vec3& b, const Vec3& c, const Bound& held, int side,
                                Bound& past) {
  const Ball ball = held.kind == Bound::point ? circumsphere(a, b, c, held.at) : equatorial_sphere(a, b, c);
  const Vec3 n = cross(b - a, c - a);
  if (!std::isfinite(ball.radius) || !(norm(n) > 0) || side == 0) return false;
  const Vec3 step = (kPastReach * ball.radius / norm(n)) * n;
  // Exact predicates on a point that overflowed say what they like (on
  // cgal_anchor_dense.off one came out (inf, nan, -inf), from a ball whose
  // centre had overflowed, before circumsphere gave those an infinite
  // radius, and two facets stopped being Delaunay).
  const auto finite = [](const Vec3& x) { return std::isfinite(x.x) && std::isfinite(x.y) && std::isfinite(x.z); };
  Vec3 far = ball.centre + step;
  if (!finite(far) || !finite(ball.centre - step)) return false;
  if (orientation(a, b, c, far) != side) far = ball.centre - step;
  if (orientation(a, b, c, far) != side) return false;
  past = {Bound::point, far};
  return outside_bound(a, b, c, far, held);
}

bool FacetWitnesses::allows(const Vec3& p, int moving) const {
  bool ok = true;
  const_cast<FacetWitnesses*>(this)->for_each_near(p, Lookup::allows, [&](const Facet& f) {
    if (has(f.v, moving)) return true;
    const Vec3 &a = points_[f.v[0]], &b = points_[f.v[1]], &c = points_[f.v[2]];
    const int side = orientation(a, b, c, p);
    // In the plane: outside every sphere of the pencil or inside all of them.
    if (side == 0) ok = side_of_equatorial_sphere(a, b, c, p) == SphereSide::outside;
    else ok = outside_bound(a, b, c, p, side > 0 ? f.below : f.above);
    return ok;
  });
  return ok;
}

bool FacetWitnesses::reshape_allows(int v, const Vec3& p) {
  // Built at the first surface move: most runs have none, and the grid of
  // every vertex was a third of this class's set-up.
  if (!grid_built_) {
    grid_.build(points_);
    grid_built_ = true;
  }
  const std::vector<char> on_hull = on_hull_planes(v, points_[v], p);
  const Vec3 from = grid_.position(v);
  grid_.update(v, p);
  bool ok = true;
  std::vector<int> occupants;
  for (size_t k = 0; k < on_hull.size() && ok; ++k) {
    Bound above, below;
    ok = reshaped_bounds(facets_of_[v][k], on_hull[k] != 0, occupants, above, below);
  }
  grid_.update(v, from);
  return ok;
}

// A hull facet of v stays on the hull where v's move from `from` to p keeps
// it in its plane exactly: an axis plane, whose coordinate the slide keeps
// (SlidePlane::onto). In another plane the slide rounds: on a plate along
// x - y = 0.25, 413 unmoved hull facets had a vertex 1 ulp beyond their
// plane after the pass (a reviewer, 2026-11-30). By v's facets.
std::vector<char> FacetWitnesses::on_hull_planes(int v, const Vec3& from, const Vec3& p) const {
  std::vector<char> on_hull(facets_of_[v].size(), 0);
  for (size_t k = 0; k < on_hull.size(); ++k) {
    const Facet& f = facets_[facets_of_[v][k]];
    if ((f.above.kind == Bound::none) == (f.below.kind == Bound::none)) continue;
    std::array<Vec3, 3> x;
    for (int j = 0; j < 3; ++j) x[j] = f.v[j] == v ? from : points_[f.v[j]];
    for (int i = 0; i < 3; ++i) on_hull[k] |= x[0][i] == x[1][i] && x[1][i] == x[2][i] && x[2][i] == p[i];
  }
  return on_hull;
}

// A reshaped facet is Delaunay when some sphere of its pencil is empty. With
// an empty equatorial sphere, that one. Else its occupants must all lie on
// one side, the occupied side: the spheres that leave all of them out lean
// towards the other side, the open one, and the one of them that allows the
// least is the occupied side's bound. On the convex hull (`on_hull`: v slid
// in its axis plane) the open side has no vertex, and its bound is none.
// Elsewhere (open_side_bound) the spheres just past that bound must leave
// out the open side's vertices too. Only an empty equatorial sphere, as
// before 2026-11-30, kept the faces of a plate 0.3 thick still: their
// facets, 1.2 wide, had vertices of the other face in theirs, and a disk's
// flat tetrahedra between the two faces' vertices (the same nodes on both)
// stayed at 0.013 deg, where slides of a vertex open them to 11 to 14 deg.
// The same held the walls of a tube 1 thick, which are not on the hull,
// until 2026-12-01.
bool FacetWitnesses::reshaped_bounds(int id, bool on_hull, std::vector<int>& occupants, Bound& above,
                                     Bound& below) const {
  const Facet& f = facets_[id];
  if (!equatorial_sphere_occupants(grid_, f.v[0], f.v[1], f.v[2], occupants)) return false;
  above = below = {Bound::equatorial, Vec3{}};
  if (!on_hull && occupants.empty()) return true;
  const Vec3 &a = grid_.position(f.v[0]), &b = grid_.position(f.v[1]), &c = grid_.position(f.v[2]);
  int occupied = 0;  // the occupants' side (orientation)
  for (const int q : occupants) {
    const int side = orientation(a, b, c, grid_.position(q));
    if (side == 0 || (occupied != 0 && side != occupied)) return false;
    occupied = side;
  }
  if (on_hull) {
    const bool open_above = f.above.kind == Bound::none;
    if (occupied != 0 && (occupied > 0) == open_above) return false;
    occupied = open_above ? -1 : 1;
  }
  Bound& held = occupied > 0 ? above : below;
  Bound& open = occupied > 0 ? below : above;
  for (const int q : occupants) {
    const Vec3& x = grid_.position(q);
    if (tightens(a, b, c, x, held)) held = {Bound::point, x};
  }
  // A bound far off the facet's size is listed in coarse cells that many
  // later lookups walk: on a foil 0.03 thick with facets 6 wide (balls of
  // radius about 180), the pass went from 34 s to past 5 minutes, 63 % of it
  // in allows() (a tester, 2026-11-30). Such a facet keeps the old rule.
  // The held bound is checked before the open side is looked for: the open
  // side's look-up reaches past it, and on c3tm_nefertiti.obj those balls
  // held 6,000 vertices on average.
  const double largest = kLargestHeldBall * equatorial_sphere(a, b, c).radius;
  const auto too_large = [&](const Bound& x) {
    return x.kind == Bound::point && !(circumsphere(a, b, c, x.at).radius <= largest);
  };
  if (too_large(held)) return false;
  if (on_hull) open = {Bound::none, Vec3{}};
  else if (!open_side_bound(a, b, c, f.v, held, -occupied, occupants, open)) return false;
  return !too_large(open);
}

// The open side's bound of a reshaped facet (a, b, c) whose occupied side
// has bound `held`: the vertex on the open side (orientation `open_side`)
// that allows the least among those in the sphere past held's (point_past),
// or that sphere's point when none is in it. False when no
// sphere between the two is empty. `scratch`: for the look-up.
bool FacetWitnesses::open_side_bound(const Vec3& a, const Vec3& b, const Vec3& c, const std::array<int, 3>& v,
                                     const Bound& held, int open_side, std::vector<int>& scratch, Bound& open) const {
  if (!point_past(a, b, c, held, open_side, open)) return false;
  const Ball reach = circumsphere(a, b, c, open.at);
  if (!std::isfinite(reach.radius)) return false;
  grid_.in_ball(reach.centre, safe_radius(reach), scratch);
  for (const int q : scratch) {
    if (q == v[0] || q == v[1] || q == v[2]) continue;
    const Vec3& x = grid_.position(q);
    const int side = orientation(a, b, c, x);
    if (side == 0) {
      // In the plane: inside every sphere of the pencil or outside all.
      if (side_of_equatorial_sphere(a, b, c, x) != SphereSide::outside) return false;
      continue;
    }
    if (side != open_side || !tightens(a, b, c, x, open)) continue;
    if (!outside_bound(a, b, c, x, held)) return false;
    open = {Bound::point, x};
  }
  return true;
}

void FacetWitnesses::moved(int v, const Vec3& p) {
  if (facets_of_[v].empty()) {
    if (grid_built_) grid_.update(v, p);  // else built from the moved points when first needed
    tighten(p, v);
    return;
  }
  // A surface vertex: reshape_allows built the grid, which still has v where it was.
  if (!grid_built_) throw std::logic_error("FacetWitnesses::moved: a surface vertex moved without reshape_allows");
  const std::vector<char> on_hull = on_hull_planes(v, grid_.position(v), p);
  grid_.update(v, p);
  tighten(p, v);
  std::vector<int> occupants;
  for (size_t k = 0; k < on_hull.size(); ++k) {
    const int id = facets_of_[v][k];
    Bound above, below;
    if (!reshaped_bounds(id, on_hull[k] != 0, occupants, above, below))
      throw std::logic_error("FacetWitnesses::moved: a reshaped facet has no bounds (reshape_allows refused it)");
    facets_[id].above = above, facets_[id].below = below;
    spread(id);
  }
}

void FacetWitnesses::tighten(const Vec3& p, int moving) {
  for_each_near(p, Lookup::tightens, [&](Facet& f) {
    if (has(f.v, moving)) return true;
    const Vec3 &a = points_[f.v[0]], &b = points_[f.v[1]], &c = points_[f.v[2]];
    const int side = orientation(a, b, c, p);
    if (side == 0) return true;
    Bound& same = side > 0 ? f.above : f.below;
    if (tightens(a, b, c, p, same)) same = {Bound::point, p};
    return true;
  });
}

FacetWitnesses::Cell FacetWitnesses::cell_of(const Vec3& p, int level) const {
  const double size = cell_ * kLevelScale[level];
  return {static_cast<std::int64_t>(std::floor(p.x / size)), static_cast<std::int64_t>(std::floor(p.y / size)),
          static_cast<std::int64_t>(std::floor(p.z / size))};
}

// Calls visit(facet) for every facet whose balls may hold p (for `lookup`),
// until it returns false.
template <class Visit>
void FacetWitnesses::for_each_near(const Vec3& p, Lookup lookup, Visit visit) {
  auto near = [&](const Facet& f) {
    ++tests_made_;
    for (int i = 0; i < 2; ++i) {
      const Ball& b = f.reach[i];
      if (f.half[i] >= 0) {
        // In the ball: on its centre's side, or in the lens behind the
        // plane (within the facet's circumcircle). allows needs the centre's
        // side only when that is not the bound's side (p is then on the
        // other side of the facet), tighten only when it is.
        const HalfSpace& h = halves_[f.half[i]];
        const Vec3 d = p - h.origin;
        const double t = dot(d, h.normal), margin = 1e-9 * norm(d) + 1e-9 * h.radius;
        const bool centre_side_counts = (lookup == Lookup::tightens) == h.centre_on_bound_side;
        if (centre_side_counts && t >= -(h.lens + margin)) return true;
        if (t >= -(h.lens + margin) && t <= margin && dot(d, d) <= (h.radius + margin) * (h.radius + margin)) return true;
        continue;
      }
      const double reach = b.radius * (1 + 1e-6);
      if (b.radius >= 0 && !(std::isfinite(reach) && dot(p - b.centre, p - b.centre) > reach * reach)) return true;
    }
    return false;
  };
  for (int id : large_)
    if (near(facets_[id]) && !visit(facets_[id])) return;
  for (int kind = lookup == Lookup::tightens ? 0 : 1; kind < 2; ++kind)
    for (const HalfSpaceGroup& g : groups_[kind]) {
      // Every member's test, (p - o).n >= -(lens + margin), bounded from
      // above over the group (its normals differ from g.normal by tilt).
      const double reach = norm(p) + g.farthest_origin;
      if (dot(p, g.normal) - g.nearest_offset + reach * g.tilt < -(g.largest_lens + 2e-9 * g.largest_radius + 4e-9 * reach))
        continue;
      for (int id : g.members)
        if (near(facets_[id]) && !visit(facets_[id])) return;
    }
  for (int level = 0; level < kLevels; ++level) {
    if (cells_[level].empty()) continue;
    auto it = cells_[level].find(cell_of(p, level));
    if (it == cells_[level].end()) continue;
    for (int id : it->second)
      if (near(facets_[id]) && !visit(facets_[id])) return;
  }
}

// (Re)computes facet id's balls from its bounds and lists it in the cells
// they cover (a listing left from earlier balls only costs a test).
void FacetWitnesses::spread(int id) {
  Facet& f = facets_[id];
  const Vec3 &a = points_[f.v[0]], &b = points_[f.v[1]], &c = points_[f.v[2]];
  const Bound* bounds[2] = {&f.above, &f.below};
  // Both sides may need the facet's circumcircle: computed once.
  const Ball circle = equatorial_sphere(a, b, c);
  double largest = -1;
  for (int i = 0; i < 2; ++i) {
    switch (bounds[i]->kind) {
      case Bound::none: f.reach[i] = Ball{Vec3{}, -1.0}; break;
      case Bound::point: f.reach[i] = circumsphere(a, b, c, bounds[i]->at); break;
      case Bound::equatorial: f.reach[i] = circle; break;
    }
    if (bounds[i]->kind == Bound::point && fill_half_space(f, i, *bounds[i], circle)) {
      join_group(id, i);
      largest = std::max(largest, halves_[f.half[i]].radius);  // its lens, listed in the cells
    } else {
      f.half[i] = -1;  // its slot in halves_ stays, unused
      largest = std::isnan(f.reach[i].radius) ? INFINITY : std::max(largest, f.reach[i].radius);
    }
  }
  // The big facets beside a finely tessellated part (the box around
  // gmsh_ellipses.brep's plates) were all in one list that every point
  // looked through: a fifth of that run. Now only flat tetrahedra's
  // (radius +inf) and the very largest balls are.
  int level = 0;
  while (level < kLevels && !(largest < kFitCells * cell_ * kLevelScale[level])) ++level;
  if (level == kLevels) {
    if (!in_large_[id]) large_.push_back(id), in_large_[id] = 1;
    return;
  }
  for (int i = 0; i < 2; ++i) {
    const Ball ball = f.half[i] >= 0 ? Ball{halves_[f.half[i]].origin, halves_[f.half[i]].radius} : f.reach[i];
    if (ball.radius < 0) continue;
    const double r = ball.radius * (1 + 1e-6) + 1e-12 * cell_;
    const Cell lo = cell_of(ball.centre - Vec3{r, r, r}, level), hi = cell_of(ball.centre + Vec3{r, r, r}, level);
    for (auto x = lo[0]; x <= hi[0]; ++x)
      for (auto y = lo[1]; y <= hi[1]; ++y)
        for (auto z = lo[2]; z <= hi[2]; ++z) {
          std::vector<int>& list = cells_[level][{x, y, z}];
          if (list.empty() || list.back() != id) list.push_back(id);
        }
  }
}

// Side i of f as a half-space when its bound q makes a ball far larger than
// the facet. With q at height e off the plane and at distance d from the
// circumcentre o in it (circumradius r), the centre is o + s n with
// s = (d^2 + e^2 - r^2) / (2 e): on q's side exactly when q is outside the
// facet's equatorial sphere (exact predicate), and a point inside the ball is
// at most r^2 / (2 |s|) = r^2 |e| / |d^2 + e^2 - r^2| behind the plane. |e| is
// bounded from above and |d^2 - r^2| from below, with margins far above the
// rounding, so the lens is an upper bound.
bool FacetWitnesses::fill_half_space(Facet& f, int i, const Bound& bound, const Ball& circle) {
  const Vec3 &a = points_[f.v[0]], &b = points_[f.v[1]], &c = points_[f.v[2]];
  const Vec3& q = bound.at;
  const double r = circle.radius;
  if (!std::isfinite(r) || !(r > 0)) return false;
  const Vec3 ab = b - a, ac = c - a, bc = c - b;
  const Vec3 cr = cross(ab, ac);
  // Skinny facets have inaccurate circumcentres and normals: the ball test.
  const double twice_area = norm(cr);
  const double longest = std::max({norm(ab), norm(ac), norm(bc)});
  if (!(twice_area > 1e-6 * longest * longest)) return false;
  const Vec3 n = (1.0 / twice_area) * cr;
  const double scale = norm(q - circle.centre) + r;
  // n is off by up to about 1e-16 |ab| |ac| / |ab x ac| <= 1e-10 rad here.
  const double e = std::abs(dot(q - a, n)) + 1e-9 * (norm(q - a) + scale);
  const Vec3 in_plane = (q - circle.centre) - dot(q - circle.centre, n) * n;
  const double gap = std::abs(dot(in_plane, in_plane) - r * r) - 1e-9 * scale * scale;
  if (!(gap > 1e-6 * r * r)) return false;
  const double lens = r * r * e / gap;
  if (!(lens < 1e-3 * r)) return false;  // not flat enough to be worth it
  const int q_side = orientation(a, b, c, q);
  if (q_side == 0) return false;
  const bool towards_q = side_of_equatorial_sphere(a, b, c, q) == SphereSide::outside;
  if (f.half[i] < 0) {
    f.half[i] = static_cast<int>(halves_.size());
    halves_.emplace_back();
  }
  HalfSpace& h = halves_[f.half[i]];
  h.origin = circle.centre;
  h.normal = (q_side > 0) == towards_q ? n : -1.0 * n;
  // Off the plane by the circumcentre's error too.
  h.lens = 2 * lens + 1e-9 * r;
  h.radius = r * (1 + 1e-6) + 1e-9 * scale;
  h.centre_on_bound_side = towards_q;
  return true;
}

void FacetWitnesses::join_group(int id, int i) {
  const Facet& f = facets_[id];
  const HalfSpace& h = halves_[f.half[i]];
  const std::int64_t key = (static_cast<std::int64_t>(f.face) << 2) | (i << 1) | (h.normal.x + h.normal.y + h.normal.z >= 0);
  const int kind = h.centre_on_bound_side ? 0 : 1;
  auto [it, fresh] = group_of_[kind].emplace(key, static_cast<int>(groups_[kind].size()));
  if (fresh) {
    groups_[kind].emplace_back();
    groups_[kind].back().normal = h.normal;
    groups_[kind].back().nearest_offset = dot(h.origin, h.normal);
  }
  HalfSpaceGroup& g = groups_[kind][it->second];
  g.nearest_offset = std::min(g.nearest_offset, dot(h.origin, g.normal));
  g.largest_lens = std::max(g.largest_lens, h.lens);
  g.tilt = std::max(g.tilt, norm(h.normal - g.normal) * (1 + 1e-9) + 1e-15);
  g.farthest_origin = std::max(g.farthest_origin, norm(h.origin));
  g.largest_radius = std::max(g.largest_radius, h.radius);
  // Listed once: a facet is spread again at every move of its vertices.
  if (!grouped_[2 * id + i]) {
    grouped_[2 * id + i] = 1;
    g.members.push_back(id);
  }
}

}  // namespace vd
