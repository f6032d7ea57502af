// OpenCASCADE's mesher sometimes puts a node a hair away from another one:
// on kicad_CP_Radial_D10.0mm.step 31 inner nodes of two fillet faces sit
// 4e-6 to 2.5e-5 from border nodes (the median edge is 0.5), and their
// triangles have angles of 0.0004 degrees. No split ever makes such a facet
// Delaunay: every mid-point lands next to the same pair of points, and
// recovery stopped with 117,592 facets missing, all of them at those nodes.
// Collapsing edges far below the chord height moves the surface by less than
// the tessellation's own error, so it is done before anything else.
//
// A vertex is removed only onto a neighbour it can move to without leaving
// its geometry: a face's inner node onto any neighbour in that face, a node
// inside a CAD edge onto its neighbour along the same edge. CAD vertices,
// poles and apexes stay.
#include <algorithm>
#include <cmath>
#include <unordered_map>

#include "cad/cad_impl.h"
#include "surface/face_patches.h"

namespace vd::cad {
namespace {

// A corner over this at an inner vertex of three facets makes it "flat". At
// 150 deg the ellipses lost 104 vertices and got 18,877 tetrahedra under 10
// deg instead of about 12,500; at 170, 19 and 12,427 (the U-joint 35 and 387,
// 29 and 382).
constexpr double kFlatCornerDeg = 170.0;

enum class Kind { inner = 0, on_edge = 1, fixed = 2 };

class Collapser {
 public:
  explicit Collapser(CadSurface& s) : s_(s) {
    const Mesh& m = s.mesh;
    const size_t n = m.points.size();
    facets_of_.resize(n);
    for (size_t f = 0; f < m.triangles.size(); ++f)
      for (int v : m.triangles[f].v) facets_of_[v].push_back(static_cast<int>(f));
    dead_.assign(m.triangles.size(), 0);
    removed_.assign(n, 0);
    classify();
  }

  // Collapses edges shorter than `max_length`, shortest first, in passes
  // until none is left that may go. Returns the number collapsed.
  int run(double max_length) {
    int total = 0;
    for (int pass = 0; pass < 8; ++pass) {
      int done = 0;
      for (const auto& [length, key] : short_edges(max_length)) {
        const int a = static_cast<int>(key >> 32), b = static_cast<int>(key & 0xffffffffu);
        if (removed_[a] || removed_[b]) continue;
        const bool a_first = kind_[a] <= kind_[b];
        if (collapse(a_first ? a : b, a_first ? b : a) || collapse(a_first ? b : a, a_first ? a : b)) ++done;
      }
      total += done;
      if (done == 0) break;
    }
    if (total) compact_surface(s_, dead_);
    return total;
  }

 private:
  void classify() {
    const Mesh& m = s_.mesh;
    const size_t n = m.points.size();
    kind_.assign(n, Kind::inner);
    cad_edge_.assign(n, -1);
    std::vector<int> spans(n, 0);
    for (const auto& [key, span] : s_.edge_spans)
      for (const int v : {static_cast<int>(key >> 32), static_cast<int>(key & 0xffffffffu)}) {
        ++spans[v];
        if (cad_edge_[v] < 0) cad_edge_[v] = span.edge;
        else if (cad_edge_[v] != span.edge) kind_[v] = Kind::fixed;  // where CAD edges meet
      }
    for (size_t v = 0; v < n; ++v) {
      if (kind_[v] == Kind::fixed) continue;
      if (s_.singular.count(static_cast<int>(v))) kind_[v] = Kind::fixed;
      else if (spans[v] == 2) kind_[v] = Kind::on_edge;
      else if (spans[v] != 0) kind_[v] = Kind::fixed;  // an edge's end
      else {
        // No CAD edge through it, yet facets of two faces: a border without
        // parameters. Leave it.
        for (int f : facets_of_[v])
          if (s_.facet_face[f] != s_.facet_face[facets_of_[v][0]]) kind_[v] = Kind::fixed;
      }
    }
  }

  std::vector<std::pair<double, std::uint64_t>> short_edges(double max_length) const {
    const Mesh& m = s_.mesh;
    std::vector<std::pair<double, std::uint64_t>> out;
    for (size_t f = 0; f < m.triangles.size(); ++f) {
      if (dead_[f]) continue;
      for (int i = 0; i < 3; ++i) {
        const int a = m.triangles[f].v[i], b = m.triangles[f].v[(i + 1) % 3];
        const double l = norm(m.points[a] - m.points[b]);
        if (l < max_length) out.emplace_back(l, edge_key(a, b));
      }
    }
    std::sort(out.begin(), out.end());
    out.erase(std::unique(out.begin(), out.end()), out.end());
    return out;
  }

  std::vector<int> neighbours(int v) const {
    std::vector<int> out;
    for (int f : facets_of_[v])
      for (int x : s_.mesh.triangles[f].v)
        if (x != v) out.push_back(x);
    std::sort(out.begin(), out.end());
    out.erase(std::unique(out.begin(), out.end()), out.end());
    return out;
  }

  // The parameter of vertex v on span `e` between v and another vertex.
  static double t_at(const CadEdgeSpan& e, int v, int other) { return v < other ? e.t_lo : e.t_hi; }

  // Moves u onto w; false (nothing changed) when u may not go there or the
  // result would fold or turn a facet by more than `max_turn_deg`.
  bool collapse(int u, int w, double max_turn_deg = 30.0) {
    if (kind_[u] == Kind::fixed) return false;
    Mesh& m = s_.mesh;
    std::vector<int> shared, others;
    for (int f : facets_of_[u]) (corner_of(m.triangles[f], w) >= 0 ? shared : others).push_back(f);
    if (shared.empty()) return false;

    // Along a CAD edge only, and only where the edge's parameter runs on
    // through u (a closed curve's start and end meet at its one vertex).
    CadEdgeSpan span_uw, span_xu;
    int x = -1;
    if (kind_[u] == Kind::on_edge) {
      const auto it = s_.edge_spans.find(edge_key(u, w));
      if (it == s_.edge_spans.end() || it->second.edge != cad_edge_[u]) return false;
      span_uw = it->second;
      for (int y : neighbours(u)) {
        if (y == w) continue;
        const auto jt = s_.edge_spans.find(edge_key(u, y));
        if (jt != s_.edge_spans.end()) x = y, span_xu = jt->second;
      }
      if (x < 0 || t_at(span_xu, u, x) != t_at(span_uw, u, w)) return false;
    }

    // Link condition: u and w have no common neighbour but the third
    // corners of their shared facets, or the surface would pinch.
    std::vector<int> apexes;
    for (int f : shared)
      for (int y : m.triangles[f].v)
        if (y != u && y != w) apexes.push_back(y);
    std::sort(apexes.begin(), apexes.end());
    apexes.erase(std::unique(apexes.begin(), apexes.end()), apexes.end());
    const std::vector<int> nu = neighbours(u), nw = neighbours(w);
    std::vector<int> common;
    std::set_intersection(nu.begin(), nu.end(), nw.begin(), nw.end(), std::back_inserter(common));
    if (common != apexes) return false;

    // Every remaining facet keeps its orientation, in space (turning by at
    // most max_turn_deg) and in its face's (u, v).
    const double cos_turn = std::cos(max_turn_deg * M_PI / 180.0);
    std::vector<gp_Pnt2d> uv_w(others.size());
    for (size_t k = 0; k < others.size(); ++k) {
      const int f = others[k];
      const Triangle& t = m.triangles[f];
      const int c = corner_of(t, u);
      std::array<int, 3> v = t.v;
      const Vec3 before = area_vector(m, v);
      v[c] = w;
      const Vec3 after = area_vector(m, v);
      const double nb = norm(before), na = norm(after);
      if (!(na > 0) || !(nb > 0) || dot(before, after) < cos_turn * na * nb) return false;
      // A wide turn is allowed to snaps only (BorderSnap), which must not
      // leave a facet between a curve and its chord.
      if (max_turn_deg > 30.0 && hugs_border(s_, v[0], v[1], v[2])) return false;
      // w's (u, v) in this face: from a shared facet of the same face, the
      // one nearest u's (u, v) here (the same side of a seam).
      bool found = false;
      double best = 0;
      for (int g : shared) {
        if (s_.facet_face[g] != s_.facet_face[f]) continue;
        const gp_Pnt2d cand = s_.uv[g][corner_of(m.triangles[g], w)];
        const double d = cand.SquareDistance(s_.uv[f][c]);
        if (!found || d < best) found = true, best = d, uv_w[k] = cand;
      }
      if (!found) return false;
      auto uv = s_.uv[f];
      const int o_before = orient2d(uv[0], uv[1], uv[2]);
      uv[c] = uv_w[k];
      if (!(o_before * orient2d(uv[0], uv[1], uv[2]) > 0)) return false;
    }

    for (int f : shared) {
      dead_[f] = 1;
      for (int y : m.triangles[f].v) {
        auto& list = facets_of_[y];
        list.erase(std::remove(list.begin(), list.end(), f), list.end());
      }
    }
    for (size_t k = 0; k < others.size(); ++k) {
      const int f = others[k];
      const int c = corner_of(m.triangles[f], u);
      m.triangles[f].v[c] = w;
      s_.uv[f][c] = uv_w[k];
      facets_of_[w].push_back(f);
    }
    facets_of_[u].clear();
    removed_[u] = 1;
    if (x >= 0) {
      const double t_x = t_at(span_xu, x, u), t_w = t_at(span_uw, w, u);
      s_.edge_spans.erase(edge_key(u, w));
      s_.edge_spans.erase(edge_key(u, x));
      s_.edge_spans[edge_key(x, w)] = x < w ? CadEdgeSpan{span_uw.edge, t_x, t_w} : CadEdgeSpan{span_uw.edge, t_w, t_x};
    }
    return true;
  }

 public:
  // Needle edges: shorter than `ratio` times the longest edge of every facet
  // on them, on faces not marked in `skip_faces`, collapsed (an inner end
  // onto the other), shortest (relative) first.
  int collapse_needle_edges(double ratio, const std::vector<char>& skip_faces) {
    const Mesh& m = s_.mesh;
    int total = 0;
    for (int pass = 0; pass < 4; ++pass) {
      // Facets of skipped faces are not looked at: an edge they share with a
      // face looked at lies on a face border, and neither of its ends is an
      // inner vertex, which a collapse needs.
      std::unordered_map<std::uint64_t, double> relative;  // edge -> largest length / longest of a facet
      for (size_t f = 0; f < m.triangles.size(); ++f) {
        if (dead_[f] || skip_faces[s_.facet_face[f]]) continue;
        const auto& v = m.triangles[f].v;
        double l[3], longest = 0;
        for (int i = 0; i < 3; ++i) longest = std::max(longest, l[i] = norm(m.points[v[i]] - m.points[v[(i + 1) % 3]]));
        for (int i = 0; i < 3; ++i) {
          double& r = relative[edge_key(v[i], v[(i + 1) % 3])];
          r = std::max(r, longest > 0 ? l[i] / longest : 1.0);
        }
      }
      std::vector<std::pair<double, std::uint64_t>> needles;
      for (const auto& [key, r] : relative)
        if (r < ratio) needles.emplace_back(r, key);
      std::sort(needles.begin(), needles.end());
      int done = 0;
      for (const auto& [r, key] : needles) {
        const int a = static_cast<int>(key >> 32), b = static_cast<int>(key & 0xffffffffu);
        if (removed_[a] || removed_[b]) continue;
        if ((kind_[a] == Kind::inner && collapse(a, b)) || (kind_[b] == Kind::inner && collapse(b, a))) ++done;
      }
      total += done;
      if (done == 0) break;
    }
    if (total) compact_surface(s_, dead_);
    return total;
  }

  // Each snap's inner vertex moved onto its node where collapse() allows
  // it. The facets around such a vertex are needles along the border, whose
  // normals a move across their width turns by anything: only a fold (in
  // space or in the face's (u, v)) or a facet left between the curve and its
  // chord stops it. Where it is stopped, a node split for it goes again
  // (onto a neighbour along its CAD edge: the facets as they were).
  int snap(const std::vector<BorderSnap>& snaps, std::vector<Vec3>* refused) {
    int done = 0;
    for (const BorderSnap& s : snaps) {
      const int u = s.vertex, w = s.node;
      if (!removed_[u] && !removed_[w] && kind_[u] == Kind::inner && collapse(u, w, 89.0)) {
        ++done;
        continue;
      }
      if (refused && !removed_[u]) refused->push_back(s_.mesh.points[u]);
      if (!s.split || removed_[w] || kind_[w] != Kind::on_edge) continue;
      for (const int x : neighbours(w))
        if (s_.edge_spans.count(edge_key(w, x)) && collapse(w, x)) break;
    }
    compact_surface(s_, dead_);
    return done;
  }

  // A face's inner vertex with three facets around it lies inside the
  // triangle of its neighbours; where one of its corners is nearly straight
  // it lies on that triangle's edge, and its facets are a cap and two
  // needles that no flip changes (the cap's long edge is the triangle's).
  // OpenCASCADE leaves such vertices on B-spline faces the remeshing keeps as
  // they are (gmsh_U_Joint_2.stp: a node 0.019 from a 3.53-long border edge,
  // a 178.4 deg facet, a 0.0007 deg tetrahedron). The three facets become the
  // triangle when the vertex lies within the face's chord height of it.
  int remove_flat_inner_vertices(const std::vector<double>& face_deflection) {
    Mesh& m = s_.mesh;
    const size_t n = m.points.size();
    // The ring's vertices of a removed one lost facets: their stars are stale.
    std::vector<char> stale(n, 0);
    const double straight = std::cos(kFlatCornerDeg * M_PI / 180.0);
    int removed = 0;
    for (size_t v = 0; v < n; ++v) {
      const std::vector<int>& around = facets_of_[v];
      if (kind_[v] != Kind::inner || stale[v] || around.size() != 3) continue;
      // The ring: each facet (v, x, y) gives the ring edge x -> y.
      std::array<int, 3> from{}, to{};
      std::array<gp_Pnt2d, 3> from_uv;
      bool flat = false;
      for (int k = 0; k < 3; ++k) {
        const Triangle& t = m.triangles[around[k]];
        const int c = corner_of(t, static_cast<int>(v));
        from[k] = t.v[(c + 1) % 3];
        to[k] = t.v[(c + 2) % 3];
        from_uv[k] = s_.uv[around[k]][(c + 1) % 3];
        const Vec3 e1 = m.points[from[k]] - m.points[v], e2 = m.points[to[k]] - m.points[v];
        flat = flat || dot(e1, e2) < straight * norm(e1) * norm(e2);
      }
      if (!flat) continue;
      // The ring closes: a -> b -> c -> a.
      std::array<int, 3> order{0, -1, -1};
      for (int step = 1; step < 3; ++step)
        for (int k = 0; k < 3; ++k)
          if (from[k] == to[order[step - 1]]) order[step] = k;
      if (order[1] < 0 || order[2] < 0 || to[order[2]] != from[order[0]]) continue;
      Triangle merged = m.triangles[around[0]];
      merged.v = {from[order[0]], from[order[1]], from[order[2]]};
      Vec3 before{0, 0, 0};
      for (int f : around) before = before + area_vector(m, m.triangles[f].v);
      const Vec3 after = area_vector(m, merged.v);
      if (!(norm(after) > 0) || !(dot(after, before) > 0)) continue;
      const double off = std::abs(dot(m.points[v] - m.points[merged.v[0]], after)) / norm(after);
      if (!(off <= face_deflection[s_.facet_face[around[0]]])) continue;
      // Only for a rounder triangle: where the neighbours' triangle is itself
      // a needle, the cap and needles may make better tetrahedra
      // (gmsh_part.step as refined and smoothed: 79 -> 92 tetrahedra under 10
      // deg, 3.04 -> 2.31 deg, without this).
      double before_corner = M_PI;
      for (int f : around) before_corner = std::min(before_corner, smallest_corner_angle(m.points, m.triangles[f]));
      if (!(smallest_corner_angle(m.points, merged) > before_corner)) continue;
      m.triangles[around[0]] = merged;
      s_.uv[around[0]] = {from_uv[order[0]], from_uv[order[1]], from_uv[order[2]]};
      dead_[around[1]] = dead_[around[2]] = 1;
      for (int x : merged.v) stale[x] = 1;
      ++removed;
    }
    if (removed) compact_surface(s_, dead_);
    return removed;
  }

 private:
  CadSurface& s_;
  std::vector<std::vector<int>> facets_of_;
  std::vector<char> dead_, removed_;
  std::vector<Kind> kind_;
  std::vector<int> cad_edge_;  // the CAD edge of an on_edge vertex
};

}  // namespace

int collapse_short_edges(CadSurface& s, double max_length) { return Collapser(s).run(max_length); }

bool hugs_border(const CadSurface& s, int x, int y, int z) {
  const int ids[3] = {x, y, z};
  int edge_of[3];
  for (int i = 0; i < 3; ++i) {
    const auto it = s.edge_spans.find(edge_key(ids[i], ids[(i + 1) % 3]));
    edge_of[i] = it == s.edge_spans.end() ? -1 - i : it->second.edge;
  }
  return edge_of[0] == edge_of[1] || edge_of[1] == edge_of[2] || edge_of[2] == edge_of[0];
}

int snap_onto_border(CadSurface& s, const std::vector<BorderSnap>& snaps, std::vector<Vec3>* refused) {
  return Collapser(s).snap(snaps, refused);
}

int collapse_needle_edges(CadSurface& s, double ratio, const std::vector<char>& skip_faces) {
  // Most parts have no face to look at: no collapser (an index of every vertex's facets) then.
  if (std::all_of(skip_faces.begin(), skip_faces.end(), [](char skip) { return skip != 0; })) return 0;
  return Collapser(s).collapse_needle_edges(ratio, skip_faces);
}

int remove_flat_inner_vertices(CadSurface& s, const std::vector<double>& face_deflection) {
  return Collapser(s).remove_flat_inner_vertices(face_deflection);
}

int compact_surface(CadSurface& s, const std::vector<char>& dead_facets) {
  Mesh& m = s.mesh;
  size_t kept = 0;
  for (size_t f = 0; f < m.triangles.size(); ++f) {
    if (!dead_facets.empty() && dead_facets[f]) continue;
    m.triangles[kept] = m.triangles[f];
    s.uv[kept] = s.uv[f];
    s.facet_face[kept] = s.facet_face[f];
    ++kept;
  }
  m.triangles.resize(kept);
  s.uv.resize(kept);
  s.facet_face.resize(kept);

  const std::vector<int> id = drop_unused_points(m);
  if (id.empty()) return 0;
  // Renumbering keeps the order of ids, so each span's t_lo stays with its lower end.
  std::unordered_map<std::uint64_t, CadEdgeSpan> spans;
  spans.reserve(s.edge_spans.size());
  for (const auto& [key, span] : s.edge_spans) {
    const int a = id[key >> 32], b = id[key & 0xffffffffu];
    if (a >= 0 && b >= 0) spans[edge_key(a, b)] = span;
  }
  s.edge_spans = std::move(spans);
  std::unordered_set<int> singular;
  for (int v : s.singular)
    if (id[v] >= 0) singular.insert(id[v]);
  s.singular = std::move(singular);
  return static_cast<int>(std::count(id.begin(), id.end(), -1));
}

}  // namespace vd::cad
