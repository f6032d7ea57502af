// The paper's IS_DELAUNAY? (§4): cheap exact sphere tests first, then Rajan's
// linear program (TET_ON_FACET) solved with GLPK. Every "Delaunay" answer is
// backed by an exact empty-sphere test of a tetrahedron having the facet as a
// face (predicates.h: a vertex ON the sphere occupies it), so an LP that went
// wrong numerically can only turn a "yes" into a "no", never the reverse.
//
// Order of the tests, and why each "yes" is sound:
//  1. stored apex: a tetrahedron (a, b, c, P) found earlier whose circumsphere
//     is still empty is strongly Delaunay, so abc is still a face.
//  2. equatorial sphere empty: that sphere witnesses abc directly.
//  3. candidate apexes: for the vertices inside the equatorial sphere, try the
//     tetrahedron they close. In general position this step is complete: the
//     spheres through a, b, c form a pencil whose centre moves along the
//     normal; if abc is Delaunay and its equatorial sphere is occupied, the
//     apex on the occupied side lies inside the equatorial sphere and is the
//     vertex of that side that the pencil meets last (largest |t| below).
//  4. TET_ON_FACET: the LP gives the Delaunay tetrahedron containing a sample
//     point X just off the facet. abc is Delaunay iff that tetrahedron (with
//     an exactly empty circumsphere) has a, b, c among its vertices.
//
// Sides. X = barycenter - K n first (n the facet normal oriented like the
// caller's `normal`, K = 1e-3 of the facet size): the paper samples "into the
// solid". An interior Delaunay facet is a face of the tetrahedra on both of
// its sides, so one side decides it: when the LP's (exactly empty)
// tetrahedron at X does not have abc as a face, the facet is not Delaunay and
// the other side is not tried. (A tetrahedron on abc flatter than the offset
// would be missed at X, but step 3 has already accepted every Delaunay facet
// with an occupied equatorial sphere, so this loses nothing in general
// position.)
//
// Hull cases. The LP is infeasible exactly when X lies outside the convex hull
// of the candidates; the box of candidates grows until it covers the whole
// point set. If X is still outside, X is outside the convex hull of all the
// vertices: abc lies on the hull (or in the plane of a hull face), and only
// the other side can hold a tetrahedron on it, so X = barycenter + K n is
// tried. A hull facet is Delaunay exactly when the tetrahedron on its inner
// side has an empty circumsphere; that is what the second side checks. If
// both sides are outside the hull (an almost flat point set, thinner than K
// near the facet), no LP applies and the facet is decided by the exact
// criterion over all vertices: of the tetrahedra abcP, only the one whose
// sphere the pencil meets first on each side can be empty; those two are
// tested exactly.
//
// The LP itself (DESIGN.md, "The linear program of §4"): unknowns λ_i for the
// vertices in a box B, rows Σλ = 1 and Σλ (P - X) = 0, objective
// Σλ |P - X|², coordinates centred on X and divided by the facet size so that
// the coefficients are O(1). It is never unbounded (λ >= 0, Σλ = 1); fewer
// than four non-zero λ means X sits on a lower-dimensional face, so X moves
// further off the facet (a few times at most).
#include <glpk.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <set>
#include <unordered_map>

#include "delaunay/oracles.h"
#include "geometry/point_grid.h"
#include "geometry/predicates.h"

namespace vd {
namespace {

constexpr double kSampleOffset = 1e-3;      // K, as a fraction of the facet size
// B's initial half-size, in equatorial radii. Measured on 2000 random points:
// 1.0 gives 44 unknowns on average (1.3 LPs per query), 1.5 gives 86 (1.05).
constexpr double kInitialBoxFactor = 1.0;
constexpr int kMaxSampleMoves = 4;          // LOWER_DIM retries
constexpr double kSampleMoveFactor = 4;     // how much further X goes per retry
constexpr int kMaxLpRounds = 64;            // safety net; B growth ends far sooner
constexpr int kCandidatesPerSide = 4;       // step 3: best few by the pencil order
constexpr double kNonZeroLambda = 1e-12;    // smaller λ: X is on a face of the tet

using FacetKey = std::array<int, 3>;
using TetKey = std::array<int, 4>;

struct FacetKeyHash {
  size_t operator()(const FacetKey& k) const {
    return (static_cast<size_t>(k[0]) * 73856093u) ^ (static_cast<size_t>(k[1]) * 19349663u) ^
           (static_cast<size_t>(k[2]) * 83492791u);
  }
};

FacetKey sorted_key(int a, int b, int c) {
  FacetKey k{a, b, c};
  std::sort(k.begin(), k.end());
  return k;
}

Box box_around(const Vec3& centre, double half) {
  const Vec3 h{half, half, half};
  return {centre - h, centre + h};
}

Box united(const Box& a, const Box& b) {
  Box u;
  for (int i = 0; i < 3; ++i) {
    u.lo[i] = std::min(a.lo[i], b.lo[i]);
    u.hi[i] = std::max(a.hi[i], b.hi[i]);
  }
  return u;
}

Box doubled(const Box& b) {
  const Vec3 centre = 0.5 * (b.lo + b.hi);
  return {centre + 2.0 * (b.lo - centre), centre + 2.0 * (b.hi - centre)};
}

// ---------------------------------------------------------------------------
// Rajan's LP with GLPK

enum class LpStatus { optimal, infeasible, lower_dimensional, failed };

struct LpSolution {
  LpStatus status = LpStatus::failed;
  TetKey tet{};  // the vertices with non-zero λ, when optimal
};

// Owns a glp_prob so that every exit path frees it.
class GlpkProblem {
 public:
  GlpkProblem() : lp_(glp_create_prob()) {}
  ~GlpkProblem() { glp_delete_prob(lp_); }
  GlpkProblem(const GlpkProblem&) = delete;
  GlpkProblem& operator=(const GlpkProblem&) = delete;
  glp_prob* get() const { return lp_; }

 private:
  glp_prob* lp_;
};

// Rows (1-based, as GLPK wants): 1: Σλ = 1; 2..4: Σλ (P - X)/scale = 0.
void load_rajan_lp(glp_prob* lp, const PointGrid& grid, const std::vector<int>& ids, const Vec3& x,
                   double scale) {
  const int n = static_cast<int>(ids.size());
  glp_set_obj_dir(lp, GLP_MIN);
  glp_add_rows(lp, 4);
  glp_set_row_bnds(lp, 1, GLP_FX, 1.0, 1.0);
  for (int row = 2; row <= 4; ++row) glp_set_row_bnds(lp, row, GLP_FX, 0.0, 0.0);
  glp_add_cols(lp, n);
  // Index 0 of GLPK's triplet arrays is unused.
  std::vector<int> ia(1), ja(1);
  std::vector<double> ar(1);
  const auto put = [&](int row, int col, double value) {
    if (value == 0) return;  // GLPK stores only non-zeros
    ia.push_back(row);
    ja.push_back(col);
    ar.push_back(value);
  };
  for (int col = 1; col <= n; ++col) {
    const Vec3 q = (1.0 / scale) * (grid.position(ids[static_cast<size_t>(col - 1)]) - x);
    glp_set_col_bnds(lp, col, GLP_LO, 0.0, 0.0);
    glp_set_obj_coef(lp, col, dot(q, q));
    put(1, col, 1.0);
    put(2, col, q.x);
    put(3, col, q.y);
    put(4, col, q.z);
  }
  glp_load_matrix(lp, static_cast<int>(ia.size()) - 1, ia.data(), ja.data(), ar.data());
}

// Runs the floating-point simplex, and GLPK's exact (rational) simplex when
// the former reports trouble: the problems are tiny, so exactness is cheap
// where it is needed. No glp_scale_prob: the coefficients are already O(1)
// (centred on X, divided by the facet size), and GLPK's automatic scaling
// costs ten times the solve itself on problems of this shape.
//
// Both are bounded in pivots: on a cube with a 1e-6 cube pushed through its
// face (a surface the self-intersection test, beside it on another thread,
// refuses), GLPK's simplex ran for minutes on one problem and the recovery
// never got to see that test's answer. Four rows take a few pivots a
// column at most; past the bound the LP counts as failed (ambiguous), as
// GLPK's own failures do.
bool run_simplex(glp_prob* lp) {
  glp_smcp parm;
  glp_init_smcp(&parm);
  parm.msg_lev = GLP_MSG_OFF;
  parm.it_lim = 1000 + 20 * (glp_get_num_rows(lp) + glp_get_num_cols(lp));
  const auto solved = [&](int rc) {
    const int status = glp_get_status(lp);
    return rc == 0 && (status == GLP_OPT || status == GLP_NOFEAS);
  };
  if (solved(glp_simplex(lp, &parm))) return true;
  glp_std_basis(lp);
  return solved(glp_exact(lp, &parm));
}

LpSolution read_solution(glp_prob* lp, const std::vector<int>& ids) {
  LpSolution s;
  if (glp_get_status(lp) == GLP_NOFEAS) {
    s.status = LpStatus::infeasible;
    return s;
  }
  // A basic solution has at most four non-zeros (four rows): the vertices of
  // the tetrahedron containing X, fewer when X is on one of its faces.
  int count = 0;
  const int n = static_cast<int>(ids.size());
  for (int col = 1; col <= n; ++col) {
    if (glp_get_col_prim(lp, col) <= kNonZeroLambda) continue;
    if (count == 4) return s;  // more than four: not a basic solution, give up
    s.tet[static_cast<size_t>(count++)] = ids[static_cast<size_t>(col - 1)];
  }
  s.status = count == 4 ? LpStatus::optimal : LpStatus::lower_dimensional;
  std::sort(s.tet.begin(), s.tet.end());
  return s;
}

LpSolution solve_rajan_lp(const PointGrid& grid, const std::vector<int>& ids, const Vec3& x,
                          double scale) {
  if (ids.empty()) return {LpStatus::infeasible, {}};
  GlpkProblem lp;
  load_rajan_lp(lp.get(), grid, ids, x, scale);
  if (!run_simplex(lp.get())) return {};
  return read_solution(lp.get(), ids);
}

// ---------------------------------------------------------------------------
// Facet geometry

struct FacetFrame {
  int a, b, c;
  Vec3 barycenter;
  Vec3 normal;     // unit, on the caller's side
  double size;     // longest edge: the paper's characteristic dimension d
  Ball equatorial;
};

// The pencil parameter of vertex p: the sphere through a, b, c centred at
// equatorial.centre + t * normal passes through p. Vertices off the plane
// enter the spheres as t moves away from them; see the header comment.
double pencil_parameter(const FacetFrame& f, const Vec3& p) {
  const Vec3 d = p - f.equatorial.centre;
  const double h = dot(d, f.normal);
  return (dot(d, d) - f.equatorial.radius * f.equatorial.radius) / (2 * h);
}

// ---------------------------------------------------------------------------

class LpOracle final : public FacetOracle {
 public:
  explicit LpOracle(const OracleOptions& options) : options_(options) { glp_term_out(GLP_OFF); }

  std::string name() const override { return "lp"; }

  void attach(const std::vector<Vec3>* points, const DelaunayTetrahedralization*) override {
    points_ = points;
    grid_.build(*points);
    apexes_.clear();
  }

  void vertex_added(int id) override { grid_.update(id, points_->at(static_cast<size_t>(id))); }

  bool is_delaunay(int a, int b, int c, Vec3 normal) override {
    ++stats_.queries;
    grid_.catch_up(*points_);
    const bool yes = decide(a, b, c, normal);
    stats_.delaunay += yes;
    return yes;
  }

 private:
  enum class SideOutcome { tetrahedron, outside_hull, refused, ambiguous };
  struct SideResult {
    SideOutcome outcome;
    TetKey tet{};
  };

  bool decide(int a, int b, int c, const Vec3& normal) {
    if (!grid_.has_triangle(a, b, c)) return false;
    const FacetKey key = sorted_key(a, b, c);
    if (stored_apex_still_empty(key)) {
      ++stats_.by_stored_apex;
      return true;
    }
    std::vector<int> occupants;
    if (!equatorial_sphere_occupants(grid_, a, b, c, occupants)) return false;
    if (occupants.empty()) {
      ++stats_.by_equatorial_sphere;
      return true;
    }
    const FacetFrame frame = facet_frame(a, b, c, normal);
    if (const int apex = empty_candidate_apex(frame, occupants); apex >= 0) {
      ++stats_.by_candidate_apex;
      remember_apex(key, apex);
      return true;
    }
    return decide_by_lp(frame);
  }

  // Step 1. A stale apex (its sphere is occupied now) is forgotten.
  bool stored_apex_still_empty(const FacetKey& key) {
    const auto it = apexes_.find(key);
    if (it == apexes_.end()) return false;
    for (int apex : it->second)
      if (apex < grid_.size() && circumsphere_is_empty(grid_, key[0], key[1], key[2], apex))
        return true;
    apexes_.erase(it);
    return false;
  }

  void remember_apex(const FacetKey& key, int apex) {
    std::vector<int>& list = apexes_[key];
    list.erase(std::remove(list.begin(), list.end(), apex), list.end());
    list.insert(list.begin(), apex);
    if (list.size() > 2) list.resize(2);  // one tetrahedron per side
  }

  // Step 3. Only the vertex the pencil meets last on each side can close an
  // empty sphere (exactly); the pencil order is computed in doubles, so the
  // best few of each side are tried, and the LP backs up a misordering.
  int empty_candidate_apex(const FacetFrame& f, const std::vector<int>& occupants) {
    std::vector<std::pair<double, int>> above, below;
    for (int id : occupants) {
      const double h = dot(grid_.position(id) - f.equatorial.centre, f.normal);
      if (h == 0) continue;  // in the facet's plane: closes no tetrahedron
      (h > 0 ? above : below).push_back({-std::abs(pencil_parameter(f, grid_.position(id))), id});
    }
    std::sort(above.begin(), above.end());
    std::sort(below.begin(), below.end());
    for (size_t i = 0; i < static_cast<size_t>(kCandidatesPerSide); ++i) {
      for (const auto* side : {&above, &below}) {
        if (i >= side->size()) continue;
        const int id = (*side)[i].second;
        if (circumsphere_is_empty(grid_, f.a, f.b, f.c, id)) return id;
      }
    }
    return -1;
  }

  // Step 4, both sides (header comment, "Sides" and "Hull cases").
  bool decide_by_lp(const FacetFrame& f) {
    for (const double side : {-1.0, 1.0}) {
      const SideResult r = tet_on_facet(f, side);
      switch (r.outcome) {
        case SideOutcome::tetrahedron:
          ++stats_.by_lp;
          return accept_if_on_facet(f, r.tet);
        case SideOutcome::refused:
          ++stats_.lp_refused_by_limit;
          return false;
        case SideOutcome::ambiguous:
          ++stats_.by_lp;
          ++stats_.lp_ambiguous;
          return false;
        case SideOutcome::outside_hull:
          break;
      }
    }
    return decide_without_lp(f);
  }

  bool accept_if_on_facet(const FacetFrame& f, const TetKey& tet) {
    int apex = -1;
    for (int v : tet)
      if (v != f.a && v != f.b && v != f.c) {
        if (apex >= 0) return false;  // two vertices off the facet
        apex = v;
      }
    if (apex < 0) return false;
    remember_apex(sorted_key(f.a, f.b, f.c), apex);
    return true;
  }

  // TET_ON_FACET at X = barycenter + side * K * normal. The returned
  // tetrahedron's circumsphere has been checked empty exactly.
  SideResult tet_on_facet(const FacetFrame& f, double side) {
    const Vec3 direction = side * f.normal;
    double offset = kSampleOffset * f.size;
    Vec3 x = f.barycenter + offset * direction;
    Box box = box_around(f.equatorial.centre, kInitialBoxFactor * f.equatorial.radius);
    std::set<TetKey> seen;
    int moves = 0;
    std::vector<int> ids;
    for (int round = 0; round < kMaxLpRounds; ++round) {
      grid_.in_box(box.lo, box.hi, ids);
      if (options_.lp_limit >= 0 && static_cast<long>(ids.size()) > options_.lp_limit)
        return {SideOutcome::refused};
      const LpSolution s = solve_rajan_lp(grid_, ids, x, f.size);
      ++stats_.lp_solved;
      stats_.lp_unknowns += static_cast<long>(ids.size());
      switch (s.status) {
        case LpStatus::infeasible:
          // X outside the candidates' hull: more candidates, until all of them.
          if (covers_all_points(box)) return {SideOutcome::outside_hull};
          box = doubled(box);
          continue;
        case LpStatus::lower_dimensional:
          if (++moves > kMaxSampleMoves) return {SideOutcome::ambiguous};
          offset *= kSampleMoveFactor;
          x = f.barycenter + offset * direction;
          continue;
        case LpStatus::failed:
          return {SideOutcome::ambiguous};
        case LpStatus::optimal:
          if (circumsphere_is_empty(grid_, s.tet[0], s.tet[1], s.tet[2], s.tet[3]))
            return {SideOutcome::tetrahedron, s.tet};
          // The candidates missed a vertex inside that sphere: take them all
          // in. The same tetrahedron again means the LP cannot see it.
          if (!seen.insert(s.tet).second) return {SideOutcome::ambiguous};
          box = united(box, box_of_circumsphere(s.tet));
          continue;
      }
    }
    return {SideOutcome::ambiguous};
  }

  bool covers_all_points(const Box& box) const {
    for (int i = 0; i < 3; ++i)
      if (box.lo[i] > grid_.lower()[i] || box.hi[i] < grid_.upper()[i]) return false;
    return true;
  }

  Box box_of_circumsphere(const TetKey& t) const {
    const Ball ball = circumsphere(grid_.position(t[0]), grid_.position(t[1]),
                                   grid_.position(t[2]), grid_.position(t[3]));
    if (!std::isfinite(ball.radius)) return {grid_.lower(), grid_.upper()};
    return box_around(ball.centre, ball.radius * (1 + 1e-6));
  }

  // Both sides outside the hull (header comment): the exact criterion over
  // all vertices, through the pencil order.
  bool decide_without_lp(const FacetFrame& f) {
    int best_above = -1, best_below = -1;
    double t_above = 0, t_below = 0;
    for (int id = 0; id < grid_.size(); ++id) {
      if (id == f.a || id == f.b || id == f.c) continue;
      const double h = dot(grid_.position(id) - f.equatorial.centre, f.normal);
      if (h == 0) continue;
      const double t = pencil_parameter(f, grid_.position(id));
      if (h > 0 && (best_above < 0 || t < t_above)) best_above = id, t_above = t;
      if (h < 0 && (best_below < 0 || t > t_below)) best_below = id, t_below = t;
    }
    for (int apex : {best_above, best_below}) {
      if (apex >= 0 && circumsphere_is_empty(grid_, f.a, f.b, f.c, apex)) {
        ++stats_.by_candidate_apex;
        remember_apex(sorted_key(f.a, f.b, f.c), apex);
        return true;
      }
    }
    return false;
  }

  FacetFrame facet_frame(int a, int b, int c, const Vec3& caller_normal) const {
    FacetFrame f{a, b, c, {}, {}, 0, {}};
    const Vec3 &pa = grid_.position(a), &pb = grid_.position(b), &pc = grid_.position(c);
    f.barycenter = (1.0 / 3.0) * (pa + pb + pc);
    Vec3 n = cross(pb - pa, pc - pa);
    if (dot(n, caller_normal) < 0) n = -1.0 * n;
    f.normal = normalized(n);
    f.size = std::max({norm(pb - pa), norm(pc - pb), norm(pa - pc)});
    f.equatorial = equatorial_sphere(pa, pb, pc);
    return f;
  }

  OracleOptions options_;
  const std::vector<Vec3>* points_ = nullptr;
  PointGrid grid_;
  // Facets found Delaunay by steps 3 and 4: the apex of the tetrahedron (one
  // per side at most) that proved it, re-checked at the next query (step 1).
  std::unordered_map<FacetKey, std::vector<int>, FacetKeyHash> apexes_;
};

}  // namespace

std::unique_ptr<FacetOracle> make_lp_oracle(const OracleOptions& options) {
  return std::make_unique<LpOracle>(options);
}

const char* lp_solver_version() { return glp_version(); }

}  // namespace vd
