#include "surface/delaunayzation.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <random>

#include "delaunay/delaunay_tetrahedralization.h"
#include "mesh/progress.h"
#include "surface/edge_map.h"
#include "surface/surface_geometry.h"
#include "surface/face_patches.h"
#include "surface/volume_keeper.h"

namespace vd {
namespace {

// A split vertex goes onto the true surface only this close to the chord,
// as a share of the narrowest split facet's height (see split_edge).
constexpr double kChordShare = 0.3;

// Patience doubles while the fewest facets missing so far are under this
// many (see stalled).
constexpr size_t kFewMissing = 100;

class Delaunayzer {
 public:
  Delaunayzer(Mesh& m, DelaunayTetrahedralization& dt, FacetOracle& oracle, const DelaunayzationOptions& o,
              EdgeMap* edges)
      : m_(m), dt_(dt), oracle_(oracle), opt_(o), rng_(o.seed), given_edges_(edges) {
    version_.assign(m_.triangles.size(), 0);
    delaunay_ = oracle_.are_delaunay(m_.triangles);
    if (delaunay_.empty()) {
      // One query a facet (the lp and sphere oracles): a surface that the
      // self-intersection test beside it refuses stops the loop (two
      // overlapping spheres of 164k facets: 2.2 s of LPs before, with the
      // refusal's answer long in).
      delaunay_.resize(m_.triangles.size());
      for (size_t f = 0; f < m_.triangles.size() && !abandoned(); ++f) {
        poll_cancel_();
        delaunay_[f] = query(m_.triangles[f]);
      }
    }
    const Box box = bounding_box(m_.points);
    min_edge_ = opt_.min_edge_relative * norm(box.hi - box.lo);
    max_added_ = opt_.max_added_vertices >= 0 ? opt_.max_added_vertices
                                              : 20 * static_cast<int>(m_.points.size()) + 1000;
    input_facets_ = static_cast<int>(m_.triangles.size());
    result_.shell_splits = opt_.shell_splits;
  }

  DelaunayzationResult run() {
    for (;;) {
      while (!guard_hit()) {
        throw_if_cancelled(opt_.cancel);
        if (abandoned()) break;
        std::vector<int> missing = non_delaunay();
        if (missing.empty() || stalled(missing.size())) break;
        // Progress: the share of the first pass's missing facets mended.
        if (first_missing_ == 0) first_missing_ = missing.size();
        set_phase_fraction(1.0 - static_cast<double>(std::min(missing.size(), first_missing_)) /
                                     static_cast<double>(first_missing_));
        index_facets();
        if (opt_.flips) flips(missing);
        splits();
        ++result_.passes;
      }
      // Never trust an oracle other than the exact tetrahedralization: a
      // facet it called Delaunay that is not goes back into the loop.
      if (oracle_.name() == "dt" || abandoned() || !demote_wrong_answers() || guard_hit()) break;
      // Facets demoted: the count of missing ones starts over.
      last_missing_ = fewest_missing_ = SIZE_MAX;
      stalled_passes_ = passes_since_fewest_ = 0;
    }
    result_.missing = non_delaunay();
    result_.added_facets = static_cast<int>(m_.triangles.size()) - input_facets_;
    return result_;
  }

 private:

  // The adjacency the flips and splits need, built once there is a facet to
  // mend (most surfaces of a volume run have none: a tenth of its recovery).
  void index_facets() {
    if (indexed_) return;
    indexed_ = true;
    edges_ = given_edges_ ? std::move(*given_edges_) : EdgeMap(m_.triangles);
    vertex_facets_.assign(m_.points.size(), {});
    for (size_t f = 0; f < m_.triangles.size(); ++f)
      for (int v : m_.triangles[f].v) vertex_facets_[v].push_back(static_cast<int>(f));
    // The regions' volumes, which only the flips and splits move.
    if (opt_.geometry && opt_.volume_limit > 0)
      volume_ = VolumeKeeper(m_, opt_.geometry->region_volumes(), opt_.volume_limit);
  }

  bool abandoned() const { return opt_.abandon && opt_.abandon->load(std::memory_order_relaxed); }

  // Called once per pass with the facets missing before it.
  bool stalled(size_t missing) {
    const bool progress = missing < last_missing_ || result_.added_vertices > last_added_;
    stalled_passes_ = progress ? 0 : stalled_passes_ + 1;
    last_missing_ = missing;
    last_added_ = result_.added_vertices;
    if (missing < fewest_missing_) fewest_missing_ = missing, passes_since_fewest_ = 0;
    else ++passes_since_fewest_;
    // With another way out, a recovery that has twice the facets it started
    // with missing and twice its fewest is running away: each pass adds more
    // vertices than the last, and none on the corpus came back
    // (gmsh_simple_plane.brep's first tessellation: 7,394 missing, then
    // 12,721, 18,199, 25,693, 36,203 ... 111,972 at the patience's 8th pass,
    // 132k vertices and 8.7 s given up; given up at 36,203 while the rule
    // asked for four times the fewest, 6.4 s, now at 18,199, 5.0 s).
    // Successful recoveries on the corpus never went past 1.5 times their
    // first count. Under kFewMissing, four times the fewest: a handful of
    // facets wanders up and down (below).
    const size_t fewest_factor = fewest_missing_ < kFewMissing ? 4 : 2;
    const bool watched = opt_.patience_passes > 0 || opt_.stop_running_away;
    const bool running_away = watched && first_missing_ > 0 && missing >= 2 * first_missing_ &&
                              missing >= fewest_factor * fewest_missing_;
    result_.ran_away = running_away;
    // With a handful of facets left, their count wanders up and down by a
    // few for a while before it falls, and the passes cost little; the way
    // out costs more: gmsh_Block.stp at twice its size had 6 missing at the
    // 8th pass, 10 at the 16th, where the patience gave it up, and none at
    // the 18th (7.19 deg smallest angle), while the unsmoothed needles of
    // its next tessellation came out at 0.01 deg, 3,176 tetrahedra under 10.
    const int patience = fewest_missing_ < kFewMissing ? 2 * opt_.patience_passes : opt_.patience_passes;
    return running_away || (opt_.max_stalled_passes > 0 && stalled_passes_ >= opt_.max_stalled_passes) ||
           (patience > 0 && passes_since_fewest_ >= patience);
  }

  bool guard_hit() const {
    return result_.passes >= opt_.max_passes || result_.added_vertices >= max_added_;
  }

  std::vector<int> non_delaunay() const {
    std::vector<int> out;
    for (size_t f = 0; f < delaunay_.size(); ++f)
      if (!delaunay_[f]) out.push_back(static_cast<int>(f));
    return out;
  }

  bool demote_wrong_answers() {
    bool any = false;
    for (size_t f = 0; f < m_.triangles.size(); ++f) {
      const auto& v = m_.triangles[f].v;
      if (delaunay_[f] && !dt_.has_facet(v[0], v[1], v[2])) {
        delaunay_[f] = false;
        ++result_.oracle_wrong;
        any = true;
      }
    }
    return any;
  }

  bool query(const Triangle& t) {
    return oracle_.is_delaunay(t.v[0], t.v[1], t.v[2], facet_area_vector(m_.points, t));
  }

  void replace_facet(int f, const Triangle& t) {
    Triangle& old = m_.triangles[f];
    edges_.remove(f, old);
    for (int v : old.v) {
      auto& list = vertex_facets_[v];
      list.erase(std::remove(list.begin(), list.end(), f), list.end());
    }
    old = t;
    edges_.add(f, t);
    for (int v : t.v) vertex_facets_[v].push_back(f);
    ++version_[f];
  }

  int append_facet(const Triangle& t) {
    const int f = static_cast<int>(m_.triangles.size());
    m_.triangles.push_back(t);
    delaunay_.push_back(false);
    version_.push_back(0);
    edges_.add(f, t);
    for (int v : t.v) vertex_facets_[v].push_back(f);
    return f;
  }

  // FLIPS: for each non-Delaunay facet, flip with the first acceptable
  // neighbour (FLIPPABLE_NEIGHBOR).
  void flips(const std::vector<int>& candidates) {
    for (int b : candidates) {
      poll_cancel_();
      if (!delaunay_[b]) try_flip(b);
    }
  }

  bool try_flip(int b) {
    const Triangle t = m_.triangles[b];
    // Edges of b, longest first.
    std::array<int, 3> order{0, 1, 2};
    auto len = [&](int i) { return norm(m_.points[t.v[(i + 1) % 3]] - m_.points[t.v[i]]); };
    std::sort(order.begin(), order.end(), [&](int i, int j) { return len(i) > len(j); });
    for (int i : order) {
      const int p = t.v[i], q = t.v[(i + 1) % 3];
      const auto& across = edges_.facets(p, q);
      if (across.size() != 2) continue;
      const int b2 = across[0] == b ? across[1] : across[0];
      const Triangle t2 = m_.triangles[b2];
      if (t2.face != t.face || t2.front != t.front || t2.back != t.back) continue;
      if (!has_directed_edge(t2, q, p)) continue;
      const int r = opposite_vertex(t, p, q), s = opposite_vertex(t2, p, q);
      if (edges_.contains(r, s)) continue;  // would make a non-manifold edge
      Triangle A = t, B = t;
      A.v = {s, q, r};
      B.v = {r, p, s};
      // On faceted input the ridge limit holds before and after: a pair
      // folded at 90 degrees inside one face id (an OBJ group around a box's
      // edge) is convex in its average plane, and flipping it would cut the
      // edge off the solid. A CAD face is smooth: its folds are chords, and
      // refusing them made recovery on the Exhaust assembly split without
      // end (226,800 added vertices, the guard).
      const bool fold_ok = opt_.geometry != nullptr || ridge_acceptable(t, t2);
      if (!convex_in_average_plane(t, t2, A, B) || !fold_ok || !ridge_acceptable(A, B)) continue;
      const double offset = face_value_or(opt_.face_flip_offset, t.face, opt_.max_flip_offset);
      if (offset > 0 && diagonal_distance(p, q, r, s) > offset) continue;
      const int before = delaunay_[b] + delaunay_[b2];
      const bool dA = query(A), dB = query(B);
      const int after = dA + dB;
      const double q_before = std::min(smallest_corner_angle(m_.points, t), smallest_corner_angle(m_.points, t2));
      const double q_after = std::min(smallest_corner_angle(m_.points, A), smallest_corner_angle(m_.points, B));
      // Delaunay count first, quality as the tie-break: the pair (count,
      // quality) grows with every flip, so flips cannot cycle.
      if (after > before || (after == before && q_after > q_before * (1 + 1e-9))) {
        volume_.record_flip(m_, t, t2, A, B);
        replace_facet(b, A);
        replace_facet(b2, B);
        delaunay_[b] = dA;
        delaunay_[b2] = dB;
        ++result_.flips;
        return true;
      }
    }
    return false;
  }

  // Convex quadrilateral, judged in projection to the average plane of the
  // pair: both new triangles keep a fair share of the projected area.
  bool convex_in_average_plane(const Triangle& t, const Triangle& t2, const Triangle& A, const Triangle& B) const {
    const Vec3 old1 = facet_area_vector(m_.points, t), old2 = facet_area_vector(m_.points, t2);
    const Vec3 n = normalized(normalized(old1) + normalized(old2));
    const double a_old1 = dot(old1, n), a_old2 = dot(old2, n);
    const double a_new1 = dot(facet_area_vector(m_.points, A), n), a_new2 = dot(facet_area_vector(m_.points, B), n);
    const double quad = a_old1 + a_old2;
    if (a_old1 <= 0 || a_old2 <= 0 || quad <= 0) return false;
    const double share = 0.02;
    return a_new1 > share * quad && a_new2 > share * quad;
  }

  // How far a flip moves the surface: between the old diagonal pq and the
  // new one rs. On a curved CAD face every flip cuts into the solid or
  // adds to it; caxif_as1-oc-214.stp's pins lost 0.85 % of their volume
  // to 7,057 flips where the tessellation itself lost 0.38 %.
  double diagonal_distance(int p, int q, int r, int s) const {
    return line_distance(m_.points[p], m_.points[q], m_.points[r], m_.points[s]);
  }

  bool ridge_acceptable(const Triangle& A, const Triangle& B) const {
    const double c = dot(normalized(facet_area_vector(m_.points, A)), normalized(facet_area_vector(m_.points, B)));
    return c >= std::cos(opt_.flip_angle_deg * M_PI / 180.0);
  }

  // SPLITS: each facet still non-Delaunay is split at its longest edge, with
  // every facet sharing that edge; then the facets the new vertex can affect
  // are checked again and FLIPS(V) runs around it.
  void splits() {
    std::vector<std::pair<int, int>> todo;
    for (size_t f = 0; f < delaunay_.size(); ++f)
      if (!delaunay_[f]) todo.emplace_back(static_cast<int>(f), version_[f]);
    for (const auto& [f, ver] : todo) {
      poll_cancel_();
      if (abandoned()) return;
      if (version_[f] != ver || delaunay_[f]) continue;
      if (result_.added_vertices >= max_added_) return;
      const Triangle& t = m_.triangles[f];
      int best = -1;
      double best_len = -1;
      for (int i = 0; i < 3; ++i) {
        const double l = norm(m_.points[t.v[(i + 1) % 3]] - m_.points[t.v[i]]);
        if (l > best_len) best_len = l, best = i;
      }
      if (best_len < min_edge_) continue;
      const int v = split_edge(t.v[best], t.v[(best + 1) % 3]);
      if (opt_.flips) flips(std::vector<int>(vertex_facets_[v]));
    }
  }

  // A vertex of the input where three or more faces meet.
  bool is_corner(int v) {
    if (corner_.empty()) {
      corner_.assign(m_.points.size(), 0);
      for (size_t u = 0; u < m_.points.size(); ++u) {
        int a = -1, b = -1;
        for (int f : vertex_facets_[u]) {
          const int face = m_.triangles[f].face;
          if (face == a || face == b) continue;
          if (a < 0) a = face;
          else if (b < 0) b = face;
          else { corner_[u] = 1; break; }
        }
      }
    }
    return v < static_cast<int>(corner_.size()) && corner_[v];
  }

  int split_edge(int p, int q) {
    std::uniform_real_distribution<double> jitter(-opt_.split_jitter, opt_.split_jitter);
    double s = 0.5 + jitter(rng_);
    if (opt_.shell_splits) {
      // Concentric shells (Ruppert; Shewchuk): an edge from a corner is
      // split at the power of two nearest its middle, measured from the
      // corner, so that the splits of the edges around it fall on common
      // spheres and stop taking each other's facets out.
      const bool cp = is_corner(p), cq = is_corner(q);
      if (cp != cq) {
        const double length = norm(m_.points[q] - m_.points[p]);
        const double r = std::exp2(std::round(std::log2(0.5 * length)));
        s = (cp ? r / length : 1.0 - r / length) + (s - 0.5);  // the same jitter
      }
    }
    const std::vector<int> sharing = edges_.facets(p, q);
    Vec3 point = m_.points[p] + s * (m_.points[q] - m_.points[p]);
    if (opt_.geometry) {
      bool on_chord = false;
      const Vec3 chord = point;
      point = place_split_point(m_, *opt_.geometry, p, q, sharing, chord, &on_chord);
      if (!on_chord && !volume_.take_split(m_, p, q, sharing, point)) {
        point = chord;
        on_chord = true;
        ++result_.splits_on_chord_for_volume;
      }
      result_.splits_on_chord += on_chord;
    }
    const int v = static_cast<int>(m_.points.size());
    m_.points.push_back(point);
    if (!m_.point_size.empty()) m_.point_size.push_back(0.5 * (m_.point_size[p] + m_.point_size[q]));
    vertex_facets_.emplace_back();
    const std::vector<int> neighbours = dt_.insert_one(point, v, p);
    oracle_.vertex_added(v);
    ++result_.splits;
    ++result_.added_vertices;

    for (int f : sharing) {
      const Triangle t = m_.triangles[f];
      const int a = has_directed_edge(t, p, q) ? p : q, b = a == p ? q : p;
      const int c = opposite_vertex(t, p, q);
      Triangle first = t, second = t;
      first.v = {a, v, c};
      second.v = {v, b, c};
      replace_facet(f, first);
      append_facet(second);
    }
    recheck_around(v, neighbours);
    return v;
  }

  // A new vertex destroys only faces whose vertices are all its Delaunay
  // neighbours, and never makes an old non-Delaunay facet Delaunay.
  void recheck_around(int v, const std::vector<int>& neighbours) {
    mark_.resize(m_.points.size(), 0);
    ++stamp_;
    mark_[v] = stamp_;
    for (int n : neighbours) mark_[n] = stamp_;
    for (int f : vertex_facets_[v]) delaunay_[f] = query(m_.triangles[f]);
    for (int n : neighbours)
      for (int f : vertex_facets_[n]) {
        if (!delaunay_[f]) continue;
        const auto& t = m_.triangles[f].v;
        if (mark_[t[0]] == stamp_ && mark_[t[1]] == stamp_ && mark_[t[2]] == stamp_)
          delaunay_[f] = query(m_.triangles[f]);
      }
  }

  Mesh& m_;
  DelaunayTetrahedralization& dt_;
  FacetOracle& oracle_;
  DelaunayzationOptions opt_;
  std::mt19937_64 rng_;
  size_t last_missing_ = SIZE_MAX, fewest_missing_ = SIZE_MAX, first_missing_ = 0;
  int last_added_ = -1, stalled_passes_ = 0, passes_since_fewest_ = 0;
  bool indexed_ = false;
  EdgeMap* given_edges_;
  EdgeMap edges_;
  std::vector<std::vector<int>> vertex_facets_;
  std::vector<char> delaunay_;
  std::vector<int> version_;
  std::vector<int> mark_;
  int stamp_ = 0;
  double min_edge_ = 0;
  int max_added_ = 0;
  int input_facets_ = 0;
  std::vector<char> corner_;  // is_corner, for the vertices before the first split
  CancelPoll poll_cancel_{opt_.cancel, 256};
  DelaunayzationResult result_;
  VolumeKeeper volume_;
};

}  // namespace

Vec3 place_split_point(const Mesh& m, const SurfaceGeometry& geometry, int p, int q, const std::vector<int>& sharing,
                       const Vec3& chord, bool* kept_on_chord) {
  std::vector<int> faces;
  for (int f : sharing) faces.push_back(m.triangles[f].face);
  // The point on the true surface, unless it is far off the chord for the
  // facets it splits: 0.3 of the narrowest one's height across the edge. On
  // a needle or cap of a curved face (OpenCASCADE makes them along narrow
  // fillets and tangent seams) the true point lies behind the neighbouring
  // needle, the next split lands next to it, and recovery never ends:
  // gmsh_Block.stp and pythonocc_Ventilator.stp added 200,000 vertices at one
  // spot and stopped at the guard. The chord keeps such facets flat, as in
  // the paper. Not much less than 0.3: at 0.1 the knife edge of
  // occt_MODERN_Exhaust_1.brep (a face rising tangentially off a plane) ends
  // with 4 facets missing, its chord points lying in the other face.
  const Vec3 placed = geometry.place_on_surface(faces, chord);
  const Vec3 edge = m.points[q] - m.points[p];
  double narrowest = norm(edge);
  for (int f : sharing) {
    const Vec3 c = m.points[opposite_vertex(m.triangles[f], p, q)];
    narrowest = std::min(narrowest, norm(cross(edge, c - m.points[p])) / norm(edge));
  }
  // And under a quarter of the edge: farther, the faces fold back on the
  // scale of the edge. Not part way either: that brought the cascades back.
  const double off = norm(placed - chord);
  const bool on_surface = off < kChordShare * narrowest && off < 0.25 * norm(edge);
  if (kept_on_chord) *kept_on_chord = !on_surface;
  return on_surface ? placed : chord;
}

DelaunayzationResult delaunayize(Mesh& surface, DelaunayTetrahedralization& dt, FacetOracle& oracle,
                                 const DelaunayzationOptions& options, EdgeMap* edges) {
  if (surface.triangles.empty()) return {};
  Delaunayzer d(surface, dt, oracle, options, edges);
  return d.run();
}

}  // namespace vd

