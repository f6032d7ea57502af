// OpenCASCADE's mesher on every face, welded into one closed surface through
// the shared edge discretisation: BRepMesh discretises each edge once, and
// each face's triangulation refers to those edge nodes through its
// Poly_PolygonOnTriangulation, so the k-th node of an edge is the same
// vertex in every face that the edge bounds (no welding by distance).
#include <BRepMesh_IncrementalMesh.hxx>
#include <BRepTools.hxx>
#include <BRep_Builder.hxx>
#include <BRep_Tool.hxx>
#include <Poly_PolygonOnTriangulation.hxx>
#include <Poly_Triangulation.hxx>
#include <TopExp.hxx>
#include <TopExp_Explorer.hxx>
#include <TopLoc_Location.hxx>
#include <TopoDS.hxx>
#include <TopoDS_Compound.hxx>
#include <TopoDS_Vertex.hxx>

#include <algorithm>
#include <array>
#include <chrono>
#include <map>

#include "cad/cad_impl.h"
#include "mesh/error.h"

namespace vd::cad {

// Which solid lies on each side of each face: OpenCASCADE orients a face of
// a solid (as met in the solid) with its surface normal pointing out of it.
// Our triangles follow the face's own (FORWARD) surface normal, so a solid
// that meets the face FORWARD is behind the triangles, REVERSED in front.
void face_sides(const CadModel::Impl& cad, std::vector<int>& front, std::vector<int>& back) {
  front.assign(cad.faces.size(), -1);
  back.assign(cad.faces.size(), -1);
  for (size_t s = 0; s < cad.solids.size(); ++s) {
    const int region = cad.solid_number[s];
    for (TopExp_Explorer ex(cad.solids[s], TopAbs_FACE); ex.More(); ex.Next()) {
      const int f = cad.face_index.FindIndex(ex.Current()) - 1;
      if (f < 0) continue;
      const TopAbs_Orientation o = ex.Current().Orientation();
      auto claim = [&](std::vector<int>& side, const char* which) {
        if (side[f] >= 0 && side[f] != region)
          throw InputError(cad.name + ": Face" + std::to_string(cad.face_number[f]) + " has Solid" +
                           std::to_string(side[f]) + " and Solid" + std::to_string(region) + " on its " + which +
                           " side: the solids overlap");
        side[f] = region;
      };
      if (o == TopAbs_FORWARD) claim(back, "inner");
      else if (o == TopAbs_REVERSED) claim(front, "outer");
      else claim(front, "outer"), claim(back, "inner");
    }
  }
  for (size_t f = 0; f < cad.faces.size(); ++f) {
    if (front[f] < 0) front[f] = 0;
    if (back[f] < 0) back[f] = 0;
  }
}

namespace {

class Welder {
 public:
  Welder(const CadModel::Impl& cad, CadSurface& out) : cad_(cad), out_(out) {
    TopExp::MapShapes(cad.shape, TopAbs_VERTEX, vertices_);
    vertex_id_.assign(vertices_.Extent() + 1, -1);
    edge_nodes_.resize(cad.edge_index.Extent() + 1);
  }

  // Global vertex ids of the nodes of face `fi`'s triangulation (1-based).
  std::vector<int> weld_face(int fi, const Handle(Poly_Triangulation) & tri, const TopLoc_Location& loc) {
    const TopoDS_Face face = TopoDS::Face(cad_.faces[fi].Oriented(TopAbs_FORWARD));
    const gp_Trsf trsf = loc.Transformation();
    auto node = [&](int i) {
      gp_Pnt p = tri->Node(i);
      if (!loc.IsIdentity()) p.Transform(trsf);
      return to_vec(p);
    };
    std::vector<int> global(tri->NbNodes() + 1, -1);
    for (TopExp_Explorer ex(face, TopAbs_EDGE); ex.More(); ex.Next()) {
      const TopoDS_Edge& edge = TopoDS::Edge(ex.Current());
      const int e = cad_.edge_index.FindIndex(edge);
      const Handle(Poly_PolygonOnTriangulation) poly = BRep_Tool::PolygonOnTriangulation(edge, tri, loc);
      if (poly.IsNull()) {
        if (BRep_Tool::Degenerated(edge)) continue;
        throw InputError(cad_.name + ": Face" + std::to_string(cad_.face_number[fi]) +
                         ": OpenCASCADE's mesher left an edge without nodes");
      }
      const int n = poly->NbNodes();
      TopoDS_Vertex v1, v2;
      TopExp::Vertices(edge, v1, v2);
      if (BRep_Tool::Degenerated(edge)) {
        for (int k = 1; k <= n; ++k) global[poly->Node(k)] = vertex_id(v1, node(poly->Node(1)));
        out_.singular.insert(vertex_id(v1, node(poly->Node(1))));
        continue;
      }
      const bool has_t = poly->HasParameters();
      const bool increasing = !has_t || poly->Parameter(1) <= poly->Parameter(n);
      auto at = [&](int k) { return increasing ? k : n + 1 - k; };  // k-th node along the edge's parameter
      std::vector<int>& inner = edge_nodes_[e];
      if (inner.empty() && n > 2) inner.assign(n - 2, -1);
      if (static_cast<int>(inner.size()) != std::max(0, n - 2))
        throw EdgeMismatchError(cad_.name + ": OpenCASCADE discretised an edge of Face" +
                                std::to_string(cad_.face_number[fi]) + " differently in two faces");
      std::vector<int> ids(n + 1);
      for (int k = 1; k <= n; ++k) {
        const int local = poly->Node(at(k));
        int id;
        if (k == 1) id = vertex_id(v1, node(local));
        else if (k == n) id = vertex_id(v2, node(local));
        else {
          int& slot = inner[k - 2];
          if (slot < 0) slot = new_vertex(node(local));
          id = slot;
        }
        global[local] = id;
        ids[k] = id;
      }
      if (has_t)
        for (int k = 1; k < n; ++k) {
          const int a = ids[k], b = ids[k + 1];
          if (a == b) continue;
          const double ta = poly->Parameter(at(k)), tb = poly->Parameter(at(k + 1));
          out_.edge_spans[edge_key(a, b)] = a < b ? CadEdgeSpan{e, ta, tb} : CadEdgeSpan{e, tb, ta};
        }
    }
    for (int i = 1; i <= tri->NbNodes(); ++i)
      if (global[i] < 0) global[i] = new_vertex(node(i));
    return global;
  }

 private:
  int new_vertex(const Vec3& p) {
    out_.mesh.points.push_back(p);
    return static_cast<int>(out_.mesh.points.size()) - 1;
  }
  int vertex_id(const TopoDS_Vertex& v, const Vec3& p) {
    const int k = vertices_.FindIndex(v);
    if (k <= 0) return new_vertex(p);
    if (vertex_id_[k] < 0) vertex_id_[k] = new_vertex(p);
    return vertex_id_[k];
  }

  const CadModel::Impl& cad_;
  CadSurface& out_;
  TopTools_IndexedMapOfShape vertices_;
  std::vector<int> vertex_id_;
  std::vector<std::vector<int>> edge_nodes_;  // per edge, its inner nodes in parameter order
};

// A face that collapses to a curve somewhere (a sliver face of zero area at
// a wing's tip, say) comes back from OpenCASCADE as pairs of triangles on the
// same three nodes, one facing each way. Each pair covers nothing and uses
// each of its edges once in each direction, so removing both keeps the
// surface closed; kept, they were refused as degenerate or duplicate facets.
// Only pairs within one face: two faces on the same nodes are a real
// (unfused) interface and stay for validation to report. Returns a flag per facet.
std::vector<char> folded_pairs(const CadSurface& s, TessellationStats& stats) {
  std::vector<std::pair<std::array<int, 3>, size_t>> by_nodes(s.mesh.triangles.size());
  for (size_t i = 0; i < by_nodes.size(); ++i) {
    by_nodes[i] = {s.mesh.triangles[i].v, i};
    std::sort(by_nodes[i].first.begin(), by_nodes[i].first.end());
  }
  std::sort(by_nodes.begin(), by_nodes.end());
  std::vector<char> drop(s.mesh.triangles.size(), 0);
  auto reversed = [](const Triangle& a, const Triangle& b) {
    for (int r = 0; r < 3; ++r)
      if (a.v[0] == b.v[r] && a.v[1] == b.v[(r + 2) % 3] && a.v[2] == b.v[(r + 1) % 3]) return true;
    return false;
  };
  for (size_t g = 0; g < by_nodes.size();) {
    size_t end = g + 1;
    while (end < by_nodes.size() && by_nodes[end].first == by_nodes[g].first) ++end;
    // Exactly two facets on these nodes, of one face, facing away from each other.
    const size_t a = by_nodes[g].second, b = end - g == 2 ? by_nodes[g + 1].second : a;
    if (a != b && s.facet_face[a] == s.facet_face[b] && reversed(s.mesh.triangles[a], s.mesh.triangles[b])) {
      drop[a] = drop[b] = 1;
      ++stats.dropped_folded;
    }
    g = end;
  }
  return drop;
}

// BRepMesh takes one chord height and one angle per call. Faces are meshed
// finest first, each call over every face at or below its chord height: a
// face meshed before keeps its triangulation (BRepMesh reuses one at least
// as fine as asked), and an edge it shares with a coarser face keeps its
// nodes, since BRepMesh takes an edge's discretisation from the finest face
// around it that it is given. The faces then weld through shared edge nodes
// as if meshed in one call. A call's angle is the smallest of its new
// faces': faces at one chord height meshed in two calls at two angles gave
// an edge of caxif_as1-oc-214.stp two discretisations (EdgeMismatchError).
void mesh_faces_by_level(const CadModel::Impl& cad, const std::vector<double>& face_deflection,
                         const std::vector<double>& face_angle_rad, const std::atomic<bool>* cancel_flag) {
  std::map<double, double> levels;  // chord height -> angle
  for (size_t f = 0; f < cad.faces.size(); ++f) {
    const auto [it, added] = levels.emplace(face_deflection[f], face_angle_rad[f]);
    if (!added) it->second = std::min(it->second, face_angle_rad[f]);
  }
  OccCancel cancel(cancel_flag);
  size_t done = 0;
  for (const auto& [deflection, angle] : levels) {
    TopoDS_Compound faces;
    BRep_Builder builder;
    builder.MakeCompound(faces);
    for (size_t f = 0; f < cad.faces.size(); ++f)
      if (face_deflection[f] <= deflection) builder.Add(faces, cad.faces[f]);
    IMeshTools_Parameters parameters;
    parameters.Deflection = deflection;
    parameters.Angle = angle;
    parameters.Relative = false;
    parameters.InParallel = false;
    BRepMesh_IncrementalMesh mesher(++done == levels.size() ? cad.shape : TopoDS_Shape(faces), parameters,
                                    cancel.range());
    cancel.check();
    if (!mesher.IsDone()) throw InputError(cad.name + ": OpenCASCADE's mesher failed on the shape");
  }
}

}  // namespace

CadSurface tessellate_faces(const CadModel::Impl& cad, const std::vector<double>& face_deflection,
                            const std::vector<double>& face_angle_rad, TessellationStats& stats,
                            const std::atomic<bool>* cancel_flag) {
  const auto t0 = std::chrono::steady_clock::now();
  // Triangulations stored in the file were made for another purpose.
  BRepTools::Clean(cad.shape);
  mesh_faces_by_level(cad, face_deflection, face_angle_rad, cancel_flag);

  CadSurface out;
  std::vector<int> front, back;
  face_sides(cad, front, back);
  Welder welder(cad, out);
  for (size_t fi = 0; fi < cad.faces.size(); ++fi) {
    const TopoDS_Face face = TopoDS::Face(cad.faces[fi].Oriented(TopAbs_FORWARD));
    TopLoc_Location loc;
    const Handle(Poly_Triangulation) tri = BRep_Tool::Triangulation(face, loc);
    if (tri.IsNull() || tri->NbTriangles() == 0)
      throw InputError(cad.name + ": Face" + std::to_string(cad.face_number[fi]) +
                       ": OpenCASCADE's mesher made no triangles (the face may be broken)");
    const std::vector<int> global = welder.weld_face(static_cast<int>(fi), tri, loc);
    stats.occ_triangles += tri->NbTriangles();
    for (int t = 1; t <= tri->NbTriangles(); ++t) {
      int n[3];
      tri->Triangle(t).Get(n[0], n[1], n[2]);
      Triangle facet;
      facet.v = {global[n[0]], global[n[1]], global[n[2]]};
      if (facet.v[0] == facet.v[1] || facet.v[1] == facet.v[2] || facet.v[0] == facet.v[2]) {
        ++stats.dropped_degenerate;
        continue;
      }
      facet.face = cad.face_number[fi];
      facet.front = front[fi];
      facet.back = back[fi];
      out.mesh.triangles.push_back(facet);
      out.facet_face.push_back(static_cast<int>(fi));
      std::array<gp_Pnt2d, 3> uv;
      if (tri->HasUVNodes())
        for (int k = 0; k < 3; ++k) uv[k] = tri->UVNode(n[k]);
      out.uv.push_back(uv);
    }
  }
  // The folded pairs go, and with them the nodes of the zero-area face
  // that no other facet uses (8 on gmsh_U_Joint_2.stp, 1e-3 of the median
  // edge off the surface: recovery stopped at them).
  compact_surface(out, folded_pairs(out, stats));
  for (size_t s = 0; s < cad.solids.size(); ++s)
    out.mesh.region_names[cad.solid_number[s]] = "Solid" + std::to_string(cad.solid_number[s]);
  // A face of its own on two input faces is named by the faces it lies
  // on (face_groups), not by its number past the input's.
  for (size_t f = 0; f < cad.faces.size(); ++f) {
    const int n = cad.face_number[f];
    const auto shared = cad.face_groups.find(n);
    if (shared == cad.face_groups.end()) {
      out.mesh.face_names[n] = "Face" + std::to_string(n);
      continue;
    }
    out.mesh.face_groups[n] = shared->second;
    for (const int g : shared->second) out.mesh.face_names[g] = "Face" + std::to_string(g);
  }
  stats.seconds_tessellate = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return out;
}

}  // namespace vd::cad
