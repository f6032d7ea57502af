// OpenCASCADE's mesher controls chord height only; this brings the
// tessellation to the requested edge length. Longest edges first, each split
// vertex evaluated on the CAD geometry: at the mid-parameter of the CAD edge
// for mesh edges on a face border, at the mid-point in the face's (u, v)
// otherwise. Then flips inside each face towards the Delaunay criterion.
#include <BRepAdaptor_Curve2d.hxx>
#include <BRep_Tool.hxx>
#include <TopoDS.hxx>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <map>
#include <memory>

#include "cad/cad_impl.h"

namespace vd::cad {
namespace {

gp_Pnt2d mid(const gp_Pnt2d& a, const gp_Pnt2d& b) { return {0.5 * (a.X() + b.X()), 0.5 * (a.Y() + b.Y())}; }

Vec3 area_vector(const Mesh& m, const std::array<int, 3>& v) {
  return cross(m.points[v[1]] - m.points[v[0]], m.points[v[2]] - m.points[v[0]]);
}

double angle_at(const Vec3& apex, const Vec3& p, const Vec3& q) {
  const Vec3 a = p - apex, b = q - apex;
  return std::atan2(norm(cross(a, b)), dot(a, b));
}

// The CAD geometry evaluated lazily, once per face and edge.
class Geometry {
 public:
  explicit Geometry(const CadModel::Impl& cad) : cad_(cad), surfaces_(cad.faces.size()), curves_(cad.edge_index.Extent() + 1) {}

  gp_Pnt on_face(int fi, const gp_Pnt2d& uv) {
    auto& s = surfaces_[fi];
    if (!s) s = std::make_unique<BRepAdaptor_Surface>(cad_.faces[fi]);
    return s->Value(uv.X(), uv.Y());
  }
  // The face point nearest to `p`, its (u, v) moved by whole periods to
  // lie nearest `near` (the facet's side of a seam).
  gp_Pnt2d project(int fi, const Vec3& p, const gp_Pnt2d& near) {
    auto it = projectors_.find(fi);
    if (it == projectors_.end()) it = projectors_.emplace(fi, FaceProjector(cad_.faces[fi])).first;
    return it->second.valid() ? it->second.uv(p, 1e-9 * cad_.diagonal, &near) : near;
  }
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
    const gp_Pnt2d a = BRepAdaptor_Curve2d(TopoDS::Edge(edge.Oriented(TopAbs_FORWARD)), face).Value(t);
    if (!BRep_Tool::IsClosed(edge, face)) return a;
    const gp_Pnt2d b = BRepAdaptor_Curve2d(TopoDS::Edge(edge.Oriented(TopAbs_REVERSED)), face).Value(t);
    return a.SquareDistance(hint) <= b.SquareDistance(hint) ? a : b;
  }

 private:
  const CadModel::Impl& cad_;
  std::vector<std::unique_ptr<BRepAdaptor_Surface>> surfaces_;
  std::vector<std::unique_ptr<BRepAdaptor_Curve>> curves_;
  std::map<int, FaceProjector> projectors_;
};

// Edge -> facets, rebuilt once per pass (sorted pairs: compact and fast).
struct EdgeFacets {
  std::vector<std::pair<std::uint64_t, int>> pairs;
  explicit EdgeFacets(const Mesh& m) {
    pairs.reserve(3 * m.triangles.size());
    for (size_t f = 0; f < m.triangles.size(); ++f)
      for (int i = 0; i < 3; ++i)
        pairs.emplace_back(edge_key(m.triangles[f].v[i], m.triangles[f].v[(i + 1) % 3]), static_cast<int>(f));
    std::sort(pairs.begin(), pairs.end());
  }
  std::vector<int> facets(std::uint64_t key) const {
    std::vector<int> out;
    auto it = std::lower_bound(pairs.begin(), pairs.end(), std::make_pair(key, -1));
    for (; it != pairs.end() && it->first == key; ++it) out.push_back(it->second);
    return out;
  }
};

int corner(const Triangle& t, int v) { return t.v[0] == v ? 0 : (t.v[1] == v ? 1 : 2); }

class Refiner {
 public:
  Refiner(const CadModel::Impl& cad, CadSurface& s, TessellationStats& stats) : geo_(cad), s_(s), stats_(stats) {}

  void split_long_edges(double size) {
    for (int pass = 0; pass < 64; ++pass) {
      const EdgeFacets map(s_.mesh);
      std::vector<std::pair<double, std::uint64_t>> long_edges;
      for (size_t i = 0; i < map.pairs.size(); ++i) {
        if (i > 0 && map.pairs[i].first == map.pairs[i - 1].first) continue;
        const std::uint64_t k = map.pairs[i].first;
        const double l = norm(s_.mesh.points[k >> 32] - s_.mesh.points[k & 0xffffffffu]);
        if (l > size) long_edges.emplace_back(l, k);
      }
      if (long_edges.empty()) return;
      std::sort(long_edges.begin(), long_edges.end(), std::greater<>());
      std::vector<char> touched(s_.mesh.triangles.size(), 0);
      for (const auto& [len, key] : long_edges) {
        std::vector<int> facets = map.facets(key);
        bool stale = false;
        for (int f : facets) stale |= touched[f] != 0;
        if (stale) continue;
        split(static_cast<int>(key >> 32), static_cast<int>(key & 0xffffffffu), facets);
        touched.resize(s_.mesh.triangles.size(), 1);
        for (int f : facets) touched[f] = 1;
      }
    }
  }

  void flip_towards_delaunay(double max_ridge_deg) {
    const double cos_limit = std::cos(max_ridge_deg * M_PI / 180.0);
    for (int pass = 0; pass < 8; ++pass) {
      const EdgeFacets map(s_.mesh);
      std::vector<char> touched(s_.mesh.triangles.size(), 0);
      int flipped = 0;
      for (size_t i = 0; i < map.pairs.size(); ++i) {
        const std::uint64_t key = map.pairs[i].first;
        if (i + 1 >= map.pairs.size() || map.pairs[i + 1].first != key) continue;
        if (i + 2 < map.pairs.size() && map.pairs[i + 2].first == key) continue;  // non-manifold
        if (i > 0 && map.pairs[i - 1].first == key) continue;
        if (s_.edge_spans.count(key)) continue;  // on a CAD edge
        const int f1 = map.pairs[i].second, f2 = map.pairs[i + 1].second;
        if (touched[f1] || touched[f2] || s_.facet_face[f1] != s_.facet_face[f2]) continue;
        if (try_flip(f1, f2, static_cast<int>(key >> 32), static_cast<int>(key & 0xffffffffu), map, cos_limit)) {
          touched[f1] = touched[f2] = 1;
          ++flipped;
        }
      }
      stats_.refine_flips += flipped;
      if (flipped == 0) return;
    }
  }

 private:
  void split(int p, int q, const std::vector<int>& facets) {
    Mesh& m = s_.mesh;
    const int v = static_cast<int>(m.points.size());
    const auto span = s_.edge_spans.find(edge_key(p, q));
    std::vector<gp_Pnt2d> uv_new(facets.size());
    Vec3 point;
    if (span != s_.edge_spans.end()) {
      const CadEdgeSpan e = span->second;
      s_.edge_spans.erase(span);
      const double t = 0.5 * (e.t_lo + e.t_hi);
      point = to_vec(geo_.on_edge(e.edge, t));
      const int lo = std::min(p, q), hi = std::max(p, q);
      s_.edge_spans[edge_key(lo, v)] = {e.edge, e.t_lo, t};
      s_.edge_spans[edge_key(hi, v)] = {e.edge, e.t_hi, t};
      for (size_t k = 0; k < facets.size(); ++k) {
        const int f = facets[k];
        const auto& uv = s_.uv[f];
        const gp_Pnt2d hint = mid(uv[corner(m.triangles[f], p)], uv[corner(m.triangles[f], q)]);
        uv_new[k] = geo_.uv_on_face(e.edge, s_.facet_face[f], t, hint);
      }
    } else {
      bool one_face = true;
      for (int f : facets) one_face &= s_.facet_face[f] == s_.facet_face[facets[0]];
      const bool singular = s_.singular.count(p) || s_.singular.count(q);
      const Vec3 chord = 0.5 * (m.points[p] + m.points[q]);
      for (size_t k = 0; k < facets.size(); ++k) {
        const int f = facets[k];
        const auto& t = m.triangles[f];
        const int cp = corner(t, p), cq = corner(t, q);
        uv_new[k] = mid(s_.uv[f][cp], s_.uv[f][cq]);
        if (singular && one_face) {
          const int regular = s_.singular.count(p) ? cq : cp;
          uv_new[k] = geo_.project(s_.facet_face[f], chord, s_.uv[f][regular]);
        }
      }
      point = one_face ? to_vec(geo_.on_face(s_.facet_face[facets[0]], uv_new[0])) : chord;
    }
    m.points.push_back(point);
    for (size_t k = 0; k < facets.size(); ++k) {
      const int f = facets[k];
      const Triangle t = m.triangles[f];
      const auto uv = s_.uv[f];
      // Rotate so that the split edge is (t.v[0], t.v[1]).
      int i = 0;
      while (!((t.v[i] == p || t.v[i] == q) && (t.v[(i + 1) % 3] == p || t.v[(i + 1) % 3] == q))) ++i;
      const int a = t.v[i], b = t.v[(i + 1) % 3], c = t.v[(i + 2) % 3];
      const gp_Pnt2d ua = uv[i], ub = uv[(i + 1) % 3], uc = uv[(i + 2) % 3];
      Triangle first = t, second = t;
      first.v = {a, v, c};
      second.v = {v, b, c};
      m.triangles[f] = first;
      s_.uv[f] = {ua, uv_new[k], uc};
      m.triangles.push_back(second);
      s_.uv.push_back({uv_new[k], ub, uc});
      s_.facet_face.push_back(s_.facet_face[f]);
    }
    ++stats_.refine_splits;
  }

  bool try_flip(int f1, int f2, int p, int q, const EdgeFacets& map, double cos_limit) {
    Mesh& m = s_.mesh;
    const Triangle t1 = m.triangles[f1], t2 = m.triangles[f2];
    const int i1 = corner(t1, p), j1 = corner(t1, q);
    // t1 = (a, b, c) with the edge directed a -> b; t2 then has b -> a.
    const int a = (j1 == (i1 + 1) % 3) ? p : q, b = a == p ? q : p;
    const int ia = corner(t1, a);
    if (t1.v[(ia + 1) % 3] != b) return false;
    const int c = t1.v[(ia + 2) % 3];
    const int ib2 = corner(t2, b);
    if (t2.v[(ib2 + 1) % 3] != a) return false;  // inconsistent orientation: leave it
    const int d = t2.v[(ib2 + 2) % 3];
    if (c == d || !map.facets(edge_key(c, d)).empty()) return false;
    const auto& P = m.points;
    if (angle_at(P[c], P[a], P[b]) + angle_at(P[d], P[b], P[a]) <= M_PI * (1 + 1e-9)) return false;
    const std::array<int, 3> n1 = {a, d, c}, n2 = {d, b, c};
    const Vec3 old_n = area_vector(m, t1.v) + area_vector(m, t2.v);
    const Vec3 A1 = area_vector(m, n1), A2 = area_vector(m, n2);
    if (dot(A1, old_n) <= 0 || dot(A2, old_n) <= 0) return false;
    const double cos_old = dot(normalized(area_vector(m, t1.v)), normalized(area_vector(m, t2.v)));
    const double cos_new = dot(normalized(A1), normalized(A2));
    if (cos_new < std::min(cos_old, cos_limit)) return false;
    const auto uv1 = s_.uv[f1], uv2 = s_.uv[f2];
    const gp_Pnt2d ua = uv1[ia], ub = uv1[(ia + 1) % 3], uc = uv1[(ia + 2) % 3], ud = uv2[(ib2 + 2) % 3];
    m.triangles[f1].v = n1;
    s_.uv[f1] = {ua, ud, uc};
    m.triangles[f2].v = n2;
    s_.uv[f2] = {ud, ub, uc};
    return true;
  }

  Geometry geo_;
  CadSurface& s_;
  TessellationStats& stats_;
};

}  // namespace

void refine_to_size(const CadModel::Impl& cad, CadSurface& s, double size, bool flips, TessellationStats& stats) {
  const auto t0 = std::chrono::steady_clock::now();
  Refiner r(cad, s, stats);
  r.split_long_edges(size);
  if (flips) r.flip_towards_delaunay(20.0);
  stats.seconds_refine = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace vd::cad
