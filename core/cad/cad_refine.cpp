// OpenCASCADE's mesher controls chord height only; this brings the
// tessellation to the requested edge length. Longest edges first, each split
// vertex evaluated on the CAD geometry: at the mid-parameter of the CAD edge
// for mesh edges on a face border, at the mid-point in the face's (u, v)
// otherwise. Then flips inside each face towards the Delaunay criterion.
#include <BRepAdaptor_Curve2d.hxx>
#include <BRep_Tool.hxx>
#include <TopoDS.hxx>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <limits>
#include <map>
#include <memory>
#include <optional>
#include <set>

#include "cad/cad_impl.h"
#include "surface/edge_map.h"
#include "surface/face_patches.h"
#include "surface/size_refinement.h"

namespace vd::cad {
namespace {

gp_Pnt2d mid(const gp_Pnt2d& a, const gp_Pnt2d& b) { return {0.5 * (a.X() + b.X()), 0.5 * (a.Y() + b.Y())}; }

// The CAD geometry evaluated lazily, once per face and edge.
class Geometry {
 public:
  explicit Geometry(const CadModel::Impl& cad) : cad_(cad), surfaces_(cad.faces.size()), curves_(cad.edge_index.Extent() + 1) {}

  gp_Pnt on_face(int fi, const gp_Pnt2d& uv) { return surface(fi).Value(uv.X(), uv.Y()); }

  // The face point nearest to `p`, its (u, v) moved by whole periods to
  // lie nearest `near` (the facet's side of a seam).
  gp_Pnt2d project(int fi, const Vec3& p, const gp_Pnt2d& near) {
    auto it = projectors_.find(fi);
    if (it == projectors_.end()) it = projectors_.emplace(fi, FaceProjector(cad_.faces[fi])).first;
    return it->second.valid() ? it->second.uv(p, 1e-9 * cad_.diagonal, &near) : near;
  }
  // The length of CAD edge e between parameters a and b (chords of 32
  // steps), and the parameter `distance` along it from a.
  double edge_length(int e, double a, double b) { return walk_edge(e, a, b, -1); }
  double parameter_at(int e, double a, double b, double distance) { return walk_edge(e, a, b, distance); }
  gp_Pnt on_edge(int e, double t) {
    auto& c = curves_[e];
    if (!c) c = std::make_unique<BRepAdaptor_Curve>(TopoDS::Edge(cad_.edge_index(e)));
    return c->Value(t);
  }
  // (u, v) of the edge point at t on face fi; a seam has two pcurves, the
  // one near `hint` (the facet's side of the seam) is taken.
  gp_Pnt2d uv_on_face(int e, int fi, double t, const gp_Pnt2d& hint) {
    const TopoDS_Edge edge = TopoDS::Edge(cad_.edge_index(e));
    const TopoDS_Face& face = cad_.faces[fi];
    // A facet on the edge from a face the edge is not on (it has no pcurve
    // there): an edge INTERNAL to one face whose ends another face shares,
    // as FreeCAD's fuse leaves where a boss touches a wall along a line
    // (BRepAdaptor_Curve2d threw, and the part was refused). Projected.
    double first = 0, last = 0;
    if (BRep_Tool::CurveOnSurface(edge, face, first, last).IsNull()) {
      const gp_Pnt p = on_edge(e, t);
      return project(fi, Vec3{p.X(), p.Y(), p.Z()}, hint);
    }
    const gp_Pnt2d a = BRepAdaptor_Curve2d(TopoDS::Edge(edge.Oriented(TopAbs_FORWARD)), face).Value(t);
    if (!BRep_Tool::IsClosed(edge, face)) return a;
    const gp_Pnt2d b = BRepAdaptor_Curve2d(TopoDS::Edge(edge.Oriented(TopAbs_REVERSED)), face).Value(t);
    return a.SquareDistance(hint) <= b.SquareDistance(hint) ? a : b;
  }

 private:
  // distance < 0: the length from a to b; else the parameter that far from a.
  double walk_edge(int e, double a, double b, double distance) {
    constexpr int kSteps = 32;
    double length = 0;
    gp_Pnt previous = on_edge(e, a);
    for (int i = 1; i <= kSteps; ++i) {
      const double t = a + (b - a) * i / kSteps;
      const gp_Pnt point = on_edge(e, t);
      const double step = previous.Distance(point);
      if (distance >= 0 && length + step >= distance)
        return a + (b - a) * (i - 1 + (step > 0 ? (distance - length) / step : 0)) / kSteps;
      length += step;
      previous = point;
    }
    return distance >= 0 ? b : length;
  }
  const CadModel::Impl& cad_;
  BRepAdaptor_Surface& surface(int fi) {
    auto& s = surfaces_[fi];
    if (!s) s = std::make_unique<BRepAdaptor_Surface>(cad_.faces[fi]);
    return *s;
  }
  std::vector<std::unique_ptr<BRepAdaptor_Surface>> surfaces_;
  std::vector<std::unique_ptr<BRepAdaptor_Curve>> curves_;
  std::map<int, FaceProjector> projectors_;
};

// Edge -> facets once, as sorted pairs (compact and fast).
struct EdgeFacets : EdgeFacetPairs {
  explicit EdgeFacets(const Mesh& m) : EdgeFacetPairs(m.triangles) {}
};

constexpr double kFlipRidgeDeg = 20.0;
// Graded sizes stop at this fraction of the size: OpenCASCADE leaves edges
// far below it (a node beside a CAD vertex), and grading down to them
// (at 0.05) split fans between two nodes of a thin fillet over and over
// (gmsh_t20_component8.step: vertices on top of each other).
constexpr double kGradedFloor = 0.2;
constexpr double kSmoothBelowDeg = 30.0;
constexpr double kSmoothTiltDeg = 30.0;
// A facet's corner over this at an inner vertex facing a border piece makes
// it a cap on the border (split_under_border_caps); each pass of snaps moves
// one row of such vertices (gmsh_ellipses.brep: 5 to 8 passes, the U-joint 4).
constexpr double kBorderCapCornerDeg = 170.0;
constexpr int kBorderCapPasses = 16;
// On a face the remeshing left and with a pole, an edge shorter than this
// times the longest edge of each of its facets is a needle's and is
// collapsed (CAD corpus, 2026-11-27: the ellipses 0.31 -> 2.19 deg,
// simple_plane 1.01 -> 1.64, the wing and fuselage 0.58 -> 0.79, the fusee
// 4.96 -> 3.91; at 0.1 the ellipses 1.00 and simple_plane 0.74. On every
// face the remeshing left it made pythonocc_11752.stp's surface cross
// itself in three more places, and took the gains of smoothing and of the
// remeshing on gmsh_part.step and a loft).
constexpr double kNeedleEdgeRatio = 0.2;

// Do the corners at c and d facing edge (a, b) sum to at most pi (by a
// relative 1e-9)? The sine of their sum decides, from cross and dot products,
// where it is clearly away from 0; corner_angle's arc tangents only where it
// is not (a sum near pi or near 2 pi, or a zero edge), so the answer is
// theirs. atan2 was 3 % of gmsh_simple_plane.brep's run, most of it here
// and in the smoothing sweeps.
bool opposite_corners_at_most_pi(const Vec3& c, const Vec3& a, const Vec3& b, const Vec3& d) {
  const Vec3 ca = a - c, cb = b - c, db = b - d, da = a - d;
  const double sin_c = norm(cross(ca, cb)), cos_c = dot(ca, cb);
  const double sin_d = norm(cross(db, da)), cos_d = dot(db, da);
  const double lengths = norm(ca) * norm(cb) * norm(db) * norm(da);
  const double sin_sum = sin_c * cos_d + cos_c * sin_d;  // times `lengths`
  if (sin_sum > 1e-8 * lengths) return true;    // the sum in (0, pi), away from pi
  if (sin_sum < -1e-8 * lengths) return false;  // in (pi, 2 pi), past pi (1 + 1e-9)
  return corner_angle(c, a, b) + corner_angle(d, b, a) <= M_PI * (1 + 1e-9);
}

class Refiner {
 public:
  Refiner(const CadModel::Impl& cad, CadSurface& s, TessellationStats& stats, double grading, double gradation)
      : geo_(cad), s_(s), grading_(grading), gradation_(gradation), stats_(stats) {}

  // Flips between the passes keep the triangles round: splitting the long
  // diagonals of OpenCASCADE's needle strips over and over put vertices at
  // 1/2, 1/4, ... 1/32 of the strip's width (a cylinder at size 0.5 got
  // edges of 0.016 and 12 times the facets it needs).
  //
  // The adjacency is kept up to date through every split and flip, and the
  // flips after a pass start from the facets it changed: rebuilding it and
  // trying every edge at each pass took 51 s of the 130 s tessellation of a
  // 1.04M-facet surface (gmsh_simple_plane.brep at its nose's chord height).
  void index_edges() { edges_ = EdgeMap(s_.mesh.triangles); }

  // The sizes of faces finer than the size (by face index; empty: none):
  // an edge is split past the smallest of its facets' faces.
  void bound_by_faces(std::vector<double> face_size) { face_size_ = std::move(face_size); }

  void split_long_edges(double size, bool flips, const std::atomic<bool>* cancel) {
    index_edges();
    if (grading_ > 0) {
      graded_ = graded_edge_sizes(s_.mesh, gradation_);
      for (double& h : graded_) h = std::max(h, kGradedFloor * size);
      sharp_corner_ = sharp_face_corners(s_.mesh, 20.0);
    }
    for (int pass = 0; pass < 64; ++pass) {
      throw_if_cancelled(cancel);
      if (flips) flip_towards_delaunay(kFlipRidgeDeg, pass == 0 ? all_edges() : edges_of_changed());
      changed_.clear();
      std::vector<std::pair<double, std::uint64_t>> long_edges;
      for (const auto& [k, around] : edges_.all()) {
        const double l = norm(s_.mesh.points[k >> 32] - s_.mesh.points[k & 0xffffffffu]);
        double edge_size = size;
        if (!face_size_.empty())
          for (const int f : around) edge_size = std::min(edge_size, face_size_[s_.facet_face[f]]);
        if (l > limit(edge_size, static_cast<int>(k >> 32), static_cast<int>(k & 0xffffffffu)) && !refused_.count(k))
          long_edges.emplace_back(l, k);
      }
      if (long_edges.empty()) return;
      std::sort(long_edges.begin(), long_edges.end(), std::greater<>());
      std::vector<char> touched(s_.mesh.triangles.size(), 0);
      for (const auto& [len, key] : long_edges) {
        std::vector<int> facets = facets_on(key);
        bool stale = false;
        for (int f : facets) stale |= touched[f] != 0;
        if (stale || refused_.count(key)) continue;
        if (!split(static_cast<int>(key >> 32), static_cast<int>(key & 0xffffffffu), facets)) {
          refused_.insert(key);
          continue;
        }
        touched.resize(s_.mesh.triangles.size(), 1);
        for (int f : facets) touched[f] = 1;
      }
    }
  }

  // Flips towards the Delaunay criterion within each face, in passes over
  // the given edges in key order, each facet flipped at most once a pass;
  // a pass goes on with the edges around its flips and those it skipped.
  // After 8 passes, what is left waits for the next call.
  void flip_towards_delaunay(double max_ridge_deg, std::vector<std::uint64_t> candidates) {
    const double cos_limit = std::cos(max_ridge_deg * M_PI / 180.0);
    candidates.insert(candidates.end(), leftover_.begin(), leftover_.end());
    for (int pass = 0; pass < 8 && !candidates.empty(); ++pass) {
      std::sort(candidates.begin(), candidates.end());
      candidates.erase(std::unique(candidates.begin(), candidates.end()), candidates.end());
      std::vector<char> touched(s_.mesh.triangles.size(), 0);
      std::vector<std::uint64_t> next;
      for (const std::uint64_t key : candidates) {
        if (s_.edge_spans.count(key)) continue;  // on a CAD edge
        const FacetList around = edges_.facets(static_cast<int>(key >> 32), static_cast<int>(key & 0xffffffffu));
        if (around.size() != 2) continue;  // gone, or non-manifold
        const int f1 = std::min(around[0], around[1]), f2 = std::max(around[0], around[1]);
        if (touched[f1] || touched[f2]) {
          next.push_back(key);
          continue;
        }
        if (s_.facet_face[f1] != s_.facet_face[f2]) continue;
        Quad o;
        if (try_flip(f1, f2, static_cast<int>(key >> 32), static_cast<int>(key & 0xffffffffu), cos_limit, o)) {
          touched[f1] = touched[f2] = 1;
          ++stats_.refine_flips;
          for (const auto& [x, y] : {std::pair{o.a, o.d}, {o.d, o.b}, {o.b, o.c}, {o.c, o.a}, {o.c, o.d}})
            next.push_back(edge_key(x, y));
        }
      }
      candidates = std::move(next);
    }
    leftover_ = std::move(candidates);
  }

  // Every edge: candidates for flip_towards_delaunay, which orders them.
  std::vector<std::uint64_t> all_edges() const {
    std::vector<std::uint64_t> keys;
    keys.reserve(edges_.all().size());
    for (const auto& [k, around] : edges_.all()) keys.push_back(k);
    return keys;
  }

  // Moves vertices inside a face towards the middle of their neighbours,
  // in the face's (u, v), each new position evaluated on the CAD face. A
  // move is kept when no facet around folds in (u, v) and it improves()
  // the corners around the vertex. Only vertices with a corner under
  // kSmoothBelowDeg or over 180 - 2 x that are tried. Returns the moves.
  int smooth_inner_vertices(int sweeps) {
    Mesh& m = s_.mesh;
    std::vector<std::vector<int>> star(m.points.size());
    for (size_t f = 0; f < m.triangles.size(); ++f)
      for (int v : m.triangles[f].v) star[v].push_back(static_cast<int>(f));
    std::vector<char> fixed = border_vertices();
    for (int v : s_.singular) fixed[v] = 1;
    for (size_t v = 0; v < m.points.size(); ++v) fixed[v] |= knife_[v];
    const double low = kSmoothBelowDeg * M_PI / 180.0, high = M_PI - 2 * low;
    const double cos_low = std::cos(low), cos_high = std::cos(high);
    int moves = 0;
    for (int sweep = 0; sweep < sweeps; ++sweep) {
      int moved = 0;
      for (size_t v = 0; v < m.points.size(); ++v) {
        const auto& around = star[v];
        if (fixed[v] || around.size() < 3) continue;
        const int face = s_.facet_face[around[0]];
        bool one_face = true;
        for (int f : around) one_face &= s_.facet_face[f] == face;
        if (!one_face) continue;
        const int vi = static_cast<int>(v);
        if (corners_clearly_within(around, cos_low, cos_high)) continue;
        const auto [smallest, largest] = corners_around(vi, around, m.points[v]);
        if (smallest >= low && largest <= high) continue;
        // The vertex's (u, v) and its neighbours' in each facet's chart.
        const gp_Pnt2d here = s_.uv[around[0]][corner_of(m.triangles[around[0]], vi)];
        double su = 0, sv = 0;
        int n = 0;
        bool one_chart = true;
        for (int f : around) {
          const Triangle& t = m.triangles[f];
          const int c = corner_of(t, vi);
          one_chart &= s_.uv[f][c].SquareDistance(here) <= 1e-24 + 1e-18 * (here.X() * here.X() + here.Y() * here.Y());
          for (int k = 1; k < 3; ++k) {
            su += s_.uv[f][(c + k) % 3].X();
            sv += s_.uv[f][(c + k) % 3].Y();
            ++n;
          }
        }
        if (!one_chart) continue;
        const gp_Pnt2d centre(su / n, sv / n);
        const Limits limits{smallest, largest, high, longest_edge_around(vi, around, m.points[v])};
        for (const double step : {1.0, 0.5}) {
          const gp_Pnt2d uv(here.X() + step * (centre.X() - here.X()), here.Y() + step * (centre.Y() - here.Y()));
          if (folds_in_uv(vi, around, uv)) continue;
          const Vec3 point = to_vec(geo_.on_face(face, uv));
          if (!improves(vi, around, point, limits)) continue;
          m.points[v] = point;
          for (int f : around) s_.uv[f][corner_of(m.triangles[f], vi)] = uv;
          ++moved;
          break;
        }
      }
      moves += moved;
      if (moved == 0) break;
    }
    return moves;
  }

 private:
  // Splits edge (p, q) of `facets`; false (nothing changed) when the new
  // vertex, placed on the CAD edge, would fold one of the halves over in
  // the face's (u, v): a thin triangle along a curved border can have its
  // third corner between the chord and the curve. A guard: it refused no
  // split on the cylinder, Exhaust, gmsh_part or wing-fuselage.
  // `from_p` > 0: on a CAD edge, the vertex goes this far from p along the
  // edge instead of to the middle of its parameters.
  bool split(int p, int q, const std::vector<int>& facets, double from_p = 0) {
    Mesh& m = s_.mesh;
    const int v = static_cast<int>(m.points.size());
    const auto span = s_.edge_spans.find(edge_key(p, q));
    std::vector<gp_Pnt2d> uv_new(facets.size());
    Vec3 point;
    double t_mid = 0;
    if (span != s_.edge_spans.end()) {
      const CadEdgeSpan& e = span->second;
      t_mid = 0.5 * (e.t_lo + e.t_hi);
      if (from_p > 0) {
        const bool p_lo = p < q;
        t_mid = geo_.parameter_at(e.edge, p_lo ? e.t_lo : e.t_hi, p_lo ? e.t_hi : e.t_lo, from_p);
      }
      point = to_vec(geo_.on_edge(e.edge, t_mid));
      for (size_t k = 0; k < facets.size(); ++k) {
        const int f = facets[k];
        const auto& uv = s_.uv[f];
        const gp_Pnt2d hint = mid(uv[corner_of(m.triangles[f], p)], uv[corner_of(m.triangles[f], q)]);
        uv_new[k] = geo_.uv_on_face(e.edge, s_.facet_face[f], t_mid, hint);
      }
    } else {
      bool one_face = true;
      for (int f : facets) one_face &= s_.facet_face[f] == s_.facet_face[facets[0]];
      const bool singular = s_.singular.count(p) || s_.singular.count(q);
      const Vec3 chord = 0.5 * (m.points[p] + m.points[q]);
      for (size_t k = 0; k < facets.size(); ++k) {
        const int f = facets[k];
        const auto& t = m.triangles[f];
        const int cp = corner_of(t, p), cq = corner_of(t, q);
        uv_new[k] = mid(s_.uv[f][cp], s_.uv[f][cq]);
        if (singular && one_face) {
          const int regular = s_.singular.count(p) ? cq : cp;
          uv_new[k] = geo_.project(s_.facet_face[f], chord, s_.uv[f][regular]);
        }
      }
      point = one_face ? to_vec(geo_.on_face(s_.facet_face[facets[0]], uv_new[0])) : chord;
    }
    // Each facet as (a, b, c) with the split edge a -> b: the corner index.
    std::vector<int> first_corner(facets.size());
    for (size_t k = 0; k < facets.size(); ++k) {
      const Triangle& t = m.triangles[facets[k]];
      int i = 0;
      while (!((t.v[i] == p || t.v[i] == q) && (t.v[(i + 1) % 3] == p || t.v[(i + 1) % 3] == q))) ++i;
      first_corner[k] = i;
      if (span == s_.edge_spans.end()) continue;
      const auto& uv = s_.uv[facets[k]];
      const gp_Pnt2d ua = uv[i], ub = uv[(i + 1) % 3], uc = uv[(i + 2) % 3];
      const int o = orient2d(ua, ub, uc);
      if (!(o * orient2d(ua, uv_new[k], uc) > 0 && o * orient2d(uv_new[k], ub, uc) > 0)) return false;
    }
    // A facet already flat along the edge (its third corner on the edge's
    // line, where a face's (u, v) folds) would get the new vertex on top of
    // that corner: a repeated vertex, split again and again by the grading.
    const double tiny = 1e-5 * norm(m.points[p] - m.points[q]);
    for (int f : facets)
      for (int c : m.triangles[f].v)
        if (norm(m.points[c] - point) <= tiny) return false;
    bool on_knife = false;
    if (span != s_.edge_spans.end()) {
      const CadEdgeSpan e = span->second;
      on_knife = knife_edges_.count(e.edge) != 0;
      s_.edge_spans.erase(span);
      const int lo = std::min(p, q), hi = std::max(p, q);
      s_.edge_spans[edge_key(lo, v)] = {e.edge, e.t_lo, t_mid};
      s_.edge_spans[edge_key(hi, v)] = {e.edge, e.t_hi, t_mid};
    }
    m.points.push_back(point);
    knife_.push_back(on_knife);
    split_edges_.insert(edge_key(p, q));
    if (grading_ > 0) {
      graded_.push_back(std::min(graded_[p], graded_[q]) + gradation_ * 0.5 * norm(m.points[p] - m.points[q]));
      sharp_corner_.push_back(0);
    }
    for (size_t k = 0; k < facets.size(); ++k) {
      const int f = facets[k];
      const Triangle t = m.triangles[f];
      const auto uv = s_.uv[f];
      const int i = first_corner[k];
      const int a = t.v[i], b = t.v[(i + 1) % 3], c = t.v[(i + 2) % 3];
      const gp_Pnt2d ua = uv[i], ub = uv[(i + 1) % 3], uc = uv[(i + 2) % 3];
      Triangle first = t, second = t;
      first.v = {a, v, c};
      second.v = {v, b, c};
      edges_.remove(f, t);
      m.triangles[f] = first;
      edges_.add(f, first);
      changed_.push_back(f);
      s_.uv[f] = {ua, uv_new[k], uc};
      edges_.add(static_cast<int>(m.triangles.size()), second);
      changed_.push_back(static_cast<int>(m.triangles.size()));
      m.triangles.push_back(second);
      s_.uv.push_back({uv_new[k], ub, uc});
      s_.facet_face.push_back(s_.facet_face[f]);
    }
    ++stats_.refine_splits;
    return true;
  }

  bool hugs_border(int x, int y, int z) const { return cad::hugs_border(s_, x, y, z); }

  // Facets f1 = (a, b, c) and f2 = (b, a, d) around edge (p, q), and the
  // corner of a in f1 and of b in f2.
  struct Quad {
    int a, b, c, d, ia, ib2;
  };
  bool quad_of(int f1, int f2, int p, int q, Quad& o) const {
    const Triangle& t1 = s_.mesh.triangles[f1];
    const Triangle& t2 = s_.mesh.triangles[f2];
    const int i1 = corner_of(t1, p), j1 = corner_of(t1, q);
    o.a = (j1 == (i1 + 1) % 3) ? p : q;
    o.b = o.a == p ? q : p;
    o.ia = corner_of(t1, o.a);
    if (t1.v[(o.ia + 1) % 3] != o.b) return false;
    o.c = t1.v[(o.ia + 2) % 3];
    o.ib2 = corner_of(t2, o.b);
    if (t2.v[(o.ib2 + 1) % 3] != o.a) return false;  // inconsistent orientation: leave it
    o.d = t2.v[(o.ib2 + 2) % 3];
    return o.c != o.d;
  }
  // (a, b, c) + (b, a, d) -> (a, d, c) + (d, b, c).
  void apply_flip(int f1, int f2, const Quad& o) {
    const auto uv1 = s_.uv[f1], uv2 = s_.uv[f2];
    const gp_Pnt2d ua = uv1[o.ia], ub = uv1[(o.ia + 1) % 3], uc = uv1[(o.ia + 2) % 3], ud = uv2[(o.ib2 + 2) % 3];
    edges_.remove(f1, s_.mesh.triangles[f1]);
    edges_.remove(f2, s_.mesh.triangles[f2]);
    s_.mesh.triangles[f1].v = {o.a, o.d, o.c};
    s_.uv[f1] = {ua, ud, uc};
    s_.mesh.triangles[f2].v = {o.d, o.b, o.c};
    s_.uv[f2] = {ud, ub, uc};
    edges_.add(f1, s_.mesh.triangles[f1]);
    edges_.add(f2, s_.mesh.triangles[f2]);
    changed_.push_back(f1);
    changed_.push_back(f2);
  }

  bool try_flip(int f1, int f2, int p, int q, double cos_limit, Quad& o) {
    Mesh& m = s_.mesh;
    if (!quad_of(f1, f2, p, q, o) || edges_.contains(o.c, o.d)) return false;
    // A split edge never comes back. On a curved face the angles facing an
    // edge can sum past pi beside a split vertex lifted off its chord (a
    // needle's base split by the grading); the flip then lays a flat
    // triangle along the old edge, which is split again on the same spot:
    // repeated vertices (gmsh_t20_component8.step).
    if (split_edges_.count(edge_key(o.c, o.d))) return false;
    const int a = o.a, b = o.b, c = o.c, d = o.d;
    if (hugs_border(a, d, c) || hugs_border(d, b, c)) return false;
    if (knife_[a] || knife_[b] || knife_[c] || knife_[d]) return false;
    const auto& P = m.points;
    if (opposite_corners_at_most_pi(P[c], P[a], P[b], P[d])) return false;
    const Vec3 old1 = area_vector(m, m.triangles[f1].v), old2 = area_vector(m, m.triangles[f2].v);
    const Vec3 A1 = area_vector(m, {a, d, c}), A2 = area_vector(m, {d, b, c});
    if (dot(A1, old1 + old2) <= 0 || dot(A2, old1 + old2) <= 0) return false;
    const double cos_old = dot(normalized(old1), normalized(old2));
    const double cos_new = dot(normalized(A1), normalized(A2));
    if (cos_new < std::min(cos_old, cos_limit)) return false;
    // The quadrilateral must be convex in the face's (u, v) too (a guard: it
    // refused no flip on the cylinder, Exhaust, gmsh_part or wing-fuselage).
    const auto& uv1 = s_.uv[f1];
    const gp_Pnt2d ua = uv1[o.ia], ub = uv1[(o.ia + 1) % 3], uc = uv1[(o.ia + 2) % 3], ud = s_.uv[f2][(o.ib2 + 2) % 3];
    const int o1 = orient2d(ua, ub, uc);
    if (!(o1 * orient2d(ua, ud, uc) > 0 && o1 * orient2d(ud, ub, uc) > 0 && o1 * orient2d(ub, ua, ud) > 0)) return false;
    apply_flip(f1, f2, o);
    return true;
  }

 public:
  // CAD edges where two faces meet at an interior angle under 60 degrees,
  // down to zero (occt_MODERN_Exhaust_1.brep has a face rising tangentially
  // off a plane): a flip next to them can lay a facet of one face across
  // the other, so facets touching their vertices are never flipped.
  void find_knife_edges() {
    const Mesh& m = s_.mesh;
    const EdgeFacets map(m);
    knife_edges_.clear();
    for (const auto& [key, span] : s_.edge_spans) {
      const std::vector<int> around = map.facets(key);
      if (around.size() != 2) continue;
      const Triangle& t1 = m.triangles[around[0]];
      const Triangle& t2 = m.triangles[around[1]];
      Vec3 n1 = normalized(area_vector(m, t1.v)), n2 = normalized(area_vector(m, t2.v));
      if (t1.front != t2.front) n2 = -1.0 * n2;  // regions swapped: normals compared as if alike
      if (dot(n1, n2) < -0.5) knife_edges_.insert(span.edge);
    }
    knife_.assign(m.points.size(), 0);
    for (const auto& [key, span] : s_.edge_spans)
      if (knife_edges_.count(span.edge)) knife_[key >> 32] = knife_[key & 0xffffffffu] = 1;
  }

  // Piece (p, q) cut at these fractions of its length from p (ascending).
  void split_at(int p, int q, const std::vector<double>& fractions) {
    const auto span = s_.edge_spans.find(edge_key(p, q));
    if (span == s_.edge_spans.end()) return;
    const CadEdgeSpan e = span->second;
    const double length = geo_.edge_length(e.edge, e.t_lo, e.t_hi);
    int at = p;
    double done = 0;
    for (double f : fractions) {
      if (!(f > 0 && f < 1)) continue;
      const std::vector<int> facets = facets_on(edge_key(at, q));
      if (facets.empty()) return;
      const int v = static_cast<int>(s_.mesh.points.size());
      if (!split(at, q, facets, f * length - done)) continue;
      at = v;
      done = f * length;
    }
  }

  // An inner vertex a hair from a border piece of its face makes a cap on
  // that piece (a corner near 180 deg) and needles beside it, which no flip
  // changes: OpenCASCADE grades the rows of some B-spline faces towards a
  // border (gmsh_ellipses.brep's ellipsoids: a first row 5e-4 from a rim
  // whose pieces are 0.08 long), and every tetrahedron on those needles is
  // flat. Each such piece is split on its CAD edge at the vertex's foot;
  // the vertex then goes onto the new node (snap_onto_border). Faces marked
  // in `skip_faces` are left. Returns the snaps, at most one per vertex and
  // piece end.
  // `refused`: positions of vertices whose snap was refused on an earlier
  // pass, not proposed again.
  std::vector<BorderSnap> split_under_border_caps(const std::vector<char>& skip_faces,
                                                  const std::set<std::array<double, 3>>& refused) {
    Mesh& m = s_.mesh;
    const auto& P = m.points;
    std::vector<char> on_border = border_vertices();
    const double cos_cap = std::cos(kBorderCapCornerDeg * M_PI / 180.0);
    std::vector<char> taken(P.size(), 0);  // a split of this pass is next to it
    std::vector<BorderSnap> snaps;
    const size_t n = m.triangles.size();
    for (size_t f = 0; f < n; ++f) {
      if (skip_faces[s_.facet_face[f]]) continue;
      const std::array<int, 3> t = m.triangles[f].v;
      for (int i = 0; i < 3; ++i) {
        const int p = t[i], q = t[(i + 1) % 3], v = t[(i + 2) % 3];
        if (on_border[v] || taken[v] || taken[p] || taken[q] || s_.singular.count(v)) continue;
        if (!refused.empty() && refused.count({P[v].x, P[v].y, P[v].z})) continue;
        const auto span = s_.edge_spans.find(edge_key(p, q));
        if (span == s_.edge_spans.end()) continue;
        const Vec3 a = P[p] - P[v], b = P[q] - P[v], pq = P[q] - P[p];
        if (!(dot(a, b) < cos_cap * norm(a) * norm(b))) continue;
        // Beside the next piece too (a facet (v, q, r) on piece (q, r)), the
        // vertex goes onto the end they share if that is the nearer end (on
        // the foot, that facet would lie between the curve and its chord);
        // else it stays. Unbounded, the U-joint's vertices went up to 2.7
        // along its borders (size 5.5), the wing and fuselage's 6.6 (36.8).
        int end = -1;
        for (const int x : {p, q})
          for (const int g : edges_.facets(v, x))
            for (const int r : m.triangles[g].v)
              if (r != v && r != x && r != p + q - x && s_.edge_spans.count(edge_key(x, r))) end = x;
        if (end >= 0) {
          if (norm(P[v] - P[end]) > 0.5 * norm(pq)) continue;
          taken[p] = taken[q] = taken[v] = 1;
          snaps.push_back({v, end, false});
          break;
        }
        const double foot = dot(P[v] - P[p], pq) / dot(pq, pq);
        const CadEdgeSpan e = span->second;
        const double along = foot * geo_.edge_length(e.edge, p < q ? e.t_lo : e.t_hi, p < q ? e.t_hi : e.t_lo);
        const int node = static_cast<int>(P.size());
        if (!split(p, q, facets_on(edge_key(p, q)), along)) continue;
        taken[p] = taken[q] = taken[v] = 1;
        taken.resize(P.size(), 1);  // facets split above hold the new node
        on_border.resize(P.size(), 1);
        snaps.push_back({v, node, true});
        break;
      }
    }
    return snaps;
  }

  // A facet with two edges on one CAD edge (three consecutive nodes of a
  // border curve) lies in the sliver between the curve and its chord; where
  // the neighbouring face meets this one at a zero angle (a knife edge), it
  // lies in that face's plane and overlaps it (occt_MODERN_Exhaust_1.brep).
  // A vertex at its centre on the CAD face lifts it off. Returns the count.
  int split_border_slivers() {
    Mesh& m = s_.mesh;
    int splits = 0;
    const size_t n = m.triangles.size();
    for (size_t f = 0; f < n; ++f) {
      const auto& v = m.triangles[f].v;
      if (!hugs_border(v[0], v[1], v[2])) continue;
      const auto uv = s_.uv[f];
      const gp_Pnt2d c((uv[0].X() + uv[1].X() + uv[2].X()) / 3, (uv[0].Y() + uv[1].Y() + uv[2].Y()) / 3);
      const int x = static_cast<int>(m.points.size());
      m.points.push_back(to_vec(geo_.on_face(s_.facet_face[f], c)));
      knife_.push_back(0);
      const Triangle t = m.triangles[f];
      for (int i = 0; i < 3; ++i) {
        Triangle child = t;
        child.v = {t.v[i], t.v[(i + 1) % 3], x};
        if (i == 0) {
          m.triangles[f] = child;
          s_.uv[f] = {uv[0], uv[1], c};
        } else {
          m.triangles.push_back(child);
          s_.uv.push_back({uv[i], uv[(i + 1) % 3], c});
          s_.facet_face.push_back(s_.facet_face[f]);
        }
      }
      ++splits;
    }
    return splits;
  }

 private:
  // Per vertex: an end of a border piece (on a CAD edge).
  std::vector<char> border_vertices() const {
    std::vector<char> on(s_.mesh.points.size(), 0);
    for (const auto& entry : s_.edge_spans) on[entry.first >> 32] = on[entry.first & 0xffffffffu] = 1;
    return on;
  }
  // What a smoothing move of a vertex must keep: its star's smallest corner
  // before (to beat), largest corner before and the cap limit, longest edge.
  struct Limits {
    double smallest, largest, cap, longest;
  };
  // Would facets around v fold over in (u, v) with v at `uv`?
  bool folds_in_uv(int v, const std::vector<int>& around, const gp_Pnt2d& uv) const {
    for (int f : around) {
      const int c = corner_of(s_.mesh.triangles[f], v);
      const auto& q = s_.uv[f];
      const gp_Pnt2d a = q[(c + 1) % 3], b = q[(c + 2) % 3];
      if (orient2d(q[c], a, b) * orient2d(uv, a, b) <= 0) return true;
    }
    return false;
  }
  // Is v at `at` better, and safe? No edge longer than the longest was,
  // and every facet nearly in its plane: longer chords on a curved face sag
  // deeper (caxif's pins lost 0.9 % of their volume), and beside a thin gap
  // (a trailing edge) a tilted facet crosses the other side's. Nor a cap
  // where there was none: a vertex drawn towards a seam made 163 deg corners
  // facing it, which no flip may cross.
  bool improves(int v, const std::vector<int>& around, const Vec3& at, const Limits& was) const {
    if (longest_edge_around(v, around, at) > was.longest || !keeps_planes(v, around, at)) return false;
    const auto [smallest, largest] = corners_around(v, around, at);
    return smallest > was.smallest && largest <= std::max(was.largest, was.cap);
  }
  double longest_edge_around(int v, const std::vector<int>& around, const Vec3& at) const {
    double most = 0;
    for (int f : around)
      for (int c : s_.mesh.triangles[f].v)
        if (c != v) most = std::max(most, norm(s_.mesh.points[c] - at));
    return most;
  }
  // Facet f's corners with its vertex v placed at `at`.
  std::array<Vec3, 3> corners_with(int f, int v, const Vec3& at) const {
    const auto& t = s_.mesh.triangles[f].v;
    const auto& P = s_.mesh.points;
    return {t[0] == v ? at : P[t[0]], t[1] == v ? at : P[t[1]], t[2] == v ? at : P[t[2]]};
  }
  // Does every facet around v keep its normal within kSmoothTiltDeg with v at `at`?
  bool keeps_planes(int v, const std::vector<int>& around, const Vec3& at) const {
    const double cos_limit = std::cos(kSmoothTiltDeg * M_PI / 180.0);
    for (int f : around) {
      const auto x = corners_with(f, v, at);
      const Vec3 now = cross(x[1] - x[0], x[2] - x[0]);
      const Vec3 was = area_vector(s_.mesh, s_.mesh.triangles[f].v);
      if (dot(now, was) <= cos_limit * norm(now) * norm(was)) return false;
    }
    return true;
  }
  // Is every corner of the facets in `around` clearly between the angles
  // whose cosines are cos_low and cos_high (cos_low > cos_high)? By cosines,
  // no arc tangent: the sweeps look at every vertex, most of which pass, and
  // atan2 was 3 % of gmsh_simple_plane.brep's run. Clearly: by 1e-9 in the
  // cosine, so a corner this calls within is within by corner_angle too.
  bool corners_clearly_within(const std::vector<int>& around, double cos_low, double cos_high) const {
    const auto& P = s_.mesh.points;
    for (int f : around) {
      const auto& t = s_.mesh.triangles[f].v;
      for (int i = 0; i < 3; ++i) {
        const Vec3 a = P[t[(i + 1) % 3]] - P[t[i]], b = P[t[(i + 2) % 3]] - P[t[i]];
        const double length = norm(a) * norm(b);
        const double c = dot(a, b);
        if (!(c < (cos_low - 1e-9) * length && c > (cos_high + 1e-9) * length)) return false;
      }
    }
    return true;
  }
  // The smallest and the largest corner of the facets around v with v at `at`.
  std::pair<double, double> corners_around(int v, const std::vector<int>& around, const Vec3& at) const {
    double least = M_PI, most = 0;
    for (int f : around) {
      const auto x = corners_with(f, v, at);
      for (int i = 0; i < 3; ++i) {
        const double a = corner_angle(x[i], x[(i + 1) % 3], x[(i + 2) % 3]);
        least = std::min(least, a);
        most = std::max(most, a);
      }
    }
    return {least, most};
  }
  // The longest edge (p, q) may be: the size, and with grading the graded
  // sizes of its ends (not at a face's sharp corner: a spike is thin by
  // design, and filling it with vertices makes flat tetrahedra).
  double limit(double size, int p, int q) const {
    if (grading_ <= 0 || sharp_corner_[p] || sharp_corner_[q] || graded_[p] <= 0 || graded_[q] <= 0) return size;
    return std::min(size, grading_ * 0.5 * (graded_[p] + graded_[q]));
  }
  // An edge's facets in increasing order (the order splits append in).
  std::vector<int> facets_on(std::uint64_t key) const {
    const auto [a, b] = edge_of_key(key);
    std::vector<int> out = edges_.facets(a, b);
    std::sort(out.begin(), out.end());
    return out;
  }
  // Candidates for flip_towards_delaunay, which orders them and drops repeats.
  std::vector<std::uint64_t> edges_of_changed() const {
    std::vector<std::uint64_t> keys;
    for (int f : changed_) {
      const auto& v = s_.mesh.triangles[f].v;
      for (int i = 0; i < 3; ++i) keys.push_back(edge_key(v[i], v[(i + 1) % 3]));
    }
    return keys;
  }

  Geometry geo_;
  CadSurface& s_;
  EdgeMap edges_;              // the surface's adjacency, from split_long_edges on
  std::vector<int> changed_;   // facets split or flipped since the last flips
  std::vector<std::uint64_t> leftover_;  // edges the last flips had no pass left for
  std::unordered_set<std::uint64_t> refused_;  // splits that would fold a facet
  std::unordered_set<std::uint64_t> split_edges_;  // never made again by a flip
  std::unordered_set<int> knife_edges_;         // CAD edge ids
  std::vector<char> knife_;                     // per vertex: on a knife edge
  double grading_ = 0, gradation_ = 0.3;
  std::vector<double> graded_;       // per vertex: graded size (with grading)
  std::vector<double> face_size_;    // bound_by_faces
  std::vector<char> sharp_corner_;   // per vertex: a face's corner under 20 deg
  TessellationStats& stats_;
};

// split_under_border_caps and snap_onto_border in passes, until a pass
// moves none and is refused none it had not been. Returns the vertices
// moved; `touched` is set when the surface changed (a snap undone renumbers
// its facets too). A refused snap is not proposed again: proposed in every
// pass, it held its piece's ends, and the vertices beside it that wanted
// them never got them (the U-joint at twice its size: two vertices refused
// at a CAD vertex in all 16 passes; 315 -> 287 tetrahedra under 10 deg).
int snap_border_caps(const CadModel::Impl& cad, CadSurface& s, TessellationStats& stats, double gradation,
                     const std::vector<char>& skip_faces, bool& touched) {
  int moved = 0;
  std::set<std::array<double, 3>> refused;  // by position: the vertices are renumbered between passes
  for (int pass = 0; pass < kBorderCapPasses; ++pass) {
    std::vector<BorderSnap> snaps;
    {
      Refiner caps(cad, s, stats, 0.0, gradation);
      caps.find_knife_edges();
      caps.index_edges();
      snaps = caps.split_under_border_caps(skip_faces, refused);
    }
    if (snaps.empty()) break;
    touched = true;
    std::vector<Vec3> now_refused;
    const int snapped = snap_onto_border(s, snaps, &now_refused);
    for (const Vec3& p : now_refused) refused.insert({p.x, p.y, p.z});
    if (snapped == 0 && now_refused.empty()) break;
    moved += snapped;
  }
  return moved;
}

}  // namespace

void refine_to_size(const CadModel::Impl& cad, CadSurface& s, const TessellationOptions& options,
                    const std::vector<double>& face_size, const std::vector<double>& face_deflection,
                    TessellationStats& stats) {
  const double size = *std::max_element(face_size.begin(), face_size.end());
  const auto t0 = std::chrono::steady_clock::now();
  std::vector<char> remeshed(cad.faces.size(), 0);
  std::optional<Refiner> r(std::in_place, cad, s, stats, options.grading, options.gradation);
  r->find_knife_edges();
  if (*std::min_element(face_size.begin(), face_size.end()) < size) r->bound_by_faces(face_size);
  stats.border_splits = r->split_border_slivers();
  r->split_long_edges(size, options.flips, options.cancel);
  if (options.flips && options.remesh) {
    // The splits above gave the borders their nodes; the faces' insides are
    // replaced, and the vertices renumbered.
    // Faces at knife edges were left until 2026-11-25: remeshed, the
    // crankshaft went 4.08 -> 15.61 deg, TSM 1.05 -> 9.83, the cylinder
    // head 0.68 -> 3.69, gmsh_dlr_f6.brep 0.79 -> 5.47, no surface crossing
    // itself on the corpus (the knife edges' own facets were split on the
    // face before, and flips still keep off them).
    const RemeshPlan plan = plan_remeshing(cad, s, face_deflection, face_size);
    for (const auto& [key, fractions] : plan.border_nodes)
      r->split_at(static_cast<int>(key >> 32), static_cast<int>(key & 0xffffffffu), fractions);
    stats.remeshed_faces = remesh_faces(cad, s, face_deflection, face_size, plan, &remeshed);
  }
  // Caps on the borders of the faces kept as they were (the remeshed ones
  // have none): each pass moves the row next to a border onto it, the next
  // pass the row behind where it is as close. The vertices renumbered, a
  // fresh refiner goes on.
  bool touched = false;
  if (options.flips) stats.border_caps_snapped = snap_border_caps(cad, s, stats, options.gradation, remeshed, touched);
  // Then the needles of the faces it left at a pole (a singular vertex):
  // OpenCASCADE's rows crowd there (an ellipsoid's, 0.003 apart along a row
  // where the rows are 0.045 apart), and no chart of ours takes a B-spline
  // face's pole.
  if (options.flips) {
    std::vector<char> away_from_poles(cad.faces.size(), 1);
    for (size_t f = 0; f < s.mesh.triangles.size(); ++f)
      for (const int v : s.mesh.triangles[f].v)
        if (s.singular.count(v) && !remeshed[s.facet_face[f]]) away_from_poles[s.facet_face[f]] = 0;
    stats.needle_edges_collapsed = collapse_needle_edges(s, kNeedleEdgeRatio, away_from_poles);
    touched = touched || stats.needle_edges_collapsed > 0;
  }
  if (stats.remeshed_faces > 0 || touched) {
    r.emplace(cad, s, stats, 0.0, options.gradation);
    r->find_knife_edges();
    r->index_edges();
  }
  if (options.flips && (options.smooth || stats.remeshed_faces > 0)) {
    // Round in the unrolled plane is not Delaunay on a cylinder: the flips
    // in 3D come after the remeshing too.
    if (options.smooth) stats.smoothing_moves = r->smooth_inner_vertices(3);
    r->flip_towards_delaunay(kFlipRidgeDeg, r->all_edges());
  }
  r.reset();  // its adjacency does not survive the renumbering
  if (options.flips) stats.flat_vertices_removed = remove_flat_inner_vertices(s, face_deflection);
  stats.seconds_refine = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace vd::cad
