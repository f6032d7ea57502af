// CadModel's surface services: the tagged tessellation at a size, the
// projector that puts Delaunayzation's split vertices on the CAD geometry,
// and the volume and area checks against OpenCASCADE.
#include <BRepAdaptor_Surface.hxx>
#include <BRepGProp.hxx>
#include <BRep_Tool.hxx>
#include <Extrema_ExtPC.hxx>
#include <GProp_GProps.hxx>
#include <Geom_Surface.hxx>
#include <ShapeAnalysis_Surface.hxx>
#include <Standard_Failure.hxx>
#include <TopExp.hxx>
#include <TopExp_Explorer.hxx>
#include <TopoDS.hxx>

#include <algorithm>
#include <cmath>
#include <map>
#include <set>

#include "cad/cad_impl.h"
#include "mesh/error.h"
#include "mesh/second_order.h"
#include "volume/region_tetrahedra.h"

namespace vd::cad {

Mesh CadModel::tessellate(const TessellationOptions& options, TessellationStats* stats_out) const {
  TessellationStats stats;
  stats.size = options.size > 0 ? options.size : default_size();
  stats.size_chosen = !(options.size > 0);
  // Chord height: a tenth of the size, and at most 1/50 of the mean
  // thickness 2V/A of the thinnest solid, so that thin parts (wings, blades)
  // keep their volume: gmsh_wing_fuselage.step lost 1.7 % of each solid at
  // size / 10, 0.49 to 0.51 % at thickness / 40 and 0.35 % at thickness / 50.
  // Per solid, not over the assembly: the thin curved plates of
  // gmsh_ellipses.brep lost 3.0 % beside their box, 1.1 % now.
  double deflection = options.deflection;
  if (!(deflection > 0)) {
    deflection = stats.size / 10.0;
    for (const auto& solid : impl_->solids) {
      GProp_GProps v, a;
      BRepGProp::VolumeProperties(solid, v);
      BRepGProp::SurfaceProperties(solid, a);
      const double volume = std::abs(v.Mass()), area = a.Mass();
      if (area > 0 && volume > 0) deflection = std::min(deflection, 2.0 * volume / area / 50.0);
    }
  }
  stats.deflection = deflection;
  try {
    CadSurface s = tessellate_faces(*impl_, deflection, options.angle_deg * M_PI / 180.0, stats, options.cancel);
    // Far below the chord height: the move is lost in the tessellation's own error.
    stats.collapsed_edges = collapse_short_edges(s, std::min(0.1 * deflection, 0.01 * stats.size));
    throw_if_cancelled(options.cancel);
    if (options.refine) refine_to_size(*impl_, s, stats.size, options.flips, stats, options.cancel);
    if (stats_out) *stats_out = stats;
    return std::move(s.mesh);
  } catch (const Standard_Failure& e) {
    throw InputError(impl_->name + ": OpenCASCADE failed while tessellating: " + e.GetMessageString());
  }
}

FaceProjector::FaceProjector(const TopoDS_Face& face) {
  const Handle(Geom_Surface) surface = BRep_Tool::Surface(face, location_);
  if (!surface.IsNull()) analyser_ = new ShapeAnalysis_Surface(surface);
}

gp_Pnt2d FaceProjector::uv(const Vec3& p, double tolerance, const gp_Pnt2d* near) const {
  gp_Pnt q(p.x, p.y, p.z);
  if (!location_.IsIdentity()) q.Transform(location_.Transformation().Inverted());
  gp_Pnt2d uv = analyser_->ValueOfUV(q, tolerance);
  if (near) {
    const Handle(Geom_Surface)& s = analyser_->Surface();
    if (s->IsUPeriodic()) uv.SetX(uv.X() + s->UPeriod() * std::round((near->X() - uv.X()) / s->UPeriod()));
    if (s->IsVPeriodic()) uv.SetY(uv.Y() + s->VPeriod() * std::round((near->Y() - uv.Y()) / s->VPeriod()));
  }
  return uv;
}

Vec3 FaceProjector::point(const gp_Pnt2d& uv) const {
  gp_Pnt on = analyser_->Value(uv);
  if (!location_.IsIdentity()) on.Transform(location_.Transformation());
  return to_vec(on);
}

namespace {

class CadGeometry : public SurfaceGeometry {
 public:
  explicit CadGeometry(const CadModel::Impl& cad) : cad_(cad) {
    // The CAD edges between each pair of faces, for splits on face borders.
    TopTools_IndexedDataMapOfShapeListOfShape edge_faces;
    for (const auto& s : cad.solids) TopExp::MapShapesAndUniqueAncestors(s, TopAbs_EDGE, TopAbs_FACE, edge_faces);
    for (int i = 1; i <= edge_faces.Extent(); ++i) {
      const TopoDS_Edge& e = TopoDS::Edge(edge_faces.FindKey(i));
      if (BRep_Tool::Degenerated(e)) continue;
      std::set<int> numbers;
      for (const TopoDS_Shape& f : edge_faces(i)) {
        const int k = cad.face_index.FindIndex(f);
        if (k > 0) numbers.insert(cad.face_number[k - 1]);
      }
      for (int a : numbers)
        for (int b : numbers)
          if (a < b) border_edges_[{a, b}].push_back(e);
      if (numbers.size() == 1) border_edges_[{*numbers.begin(), *numbers.begin()}].push_back(e);  // seams
    }
  }

  Vec3 place_on_surface(const std::vector<int>& faces, const Vec3& chord) const override {
    std::set<int> distinct(faces.begin(), faces.end());
    try {
      if (distinct.size() == 1) return on_face(*distinct.begin(), chord);
      if (distinct.size() == 2) {
        // Between two curved faces a border point goes onto their CAD edge.
        // Next to a plane it stays on the chord, which lies in the plane:
        // on gmsh_part.step, points put on the circle between a plane and a
        // cylinder made Delaunayzation split without end (88,660 added
        // vertices, the guard), while the chord converges.
        const int a = *distinct.begin(), b = *distinct.rbegin();
        const bool plane_a = is_plane(a), plane_b = is_plane(b);
        if (plane_a || plane_b) return chord;
        return on_border(a, b, chord);
      }
    } catch (const Standard_Failure&) {
      // No projection: the chord is the paper's place anyway.
    }
    return chord;
  }

  // Unlike a split vertex, a node goes onto the CAD edge next to a plane too:
  // the circle where a cylinder meets a plane is where it belongs.
  Vec3 place_node(const std::vector<int>& faces, const Vec3& chord) const override {
    std::set<int> distinct(faces.begin(), faces.end());
    try {
      if (distinct.size() == 1) return on_face(*distinct.begin(), chord);
      if (distinct.size() == 2) return on_border(*distinct.begin(), *distinct.rbegin(), chord);
    } catch (const Standard_Failure&) {
    }
    return chord;
  }

 private:
  Vec3 on_face(int number, const Vec3& p) const {
    const int fi = cad_.index_of_face_number(number);
    if (fi < 0) return p;
    auto it = projectors_.find(fi);
    if (it == projectors_.end()) it = projectors_.emplace(fi, FaceProjector(cad_.faces[fi])).first;
    const FaceProjector& face = it->second;
    return face.valid() ? face.point(face.uv(p, 1e-9 * cad_.diagonal)) : p;
  }

  bool is_plane(int number) const {
    const int fi = cad_.index_of_face_number(number);
    if (fi < 0) return false;
    auto it = plane_.find(fi);
    if (it == plane_.end())
      it = plane_.emplace(fi, BRepAdaptor_Surface(cad_.faces[fi]).GetType() == GeomAbs_Plane).first;
    return it->second;
  }

  Vec3 on_border(int a, int b, const Vec3& p) const {
    auto it = border_edges_.find({a, b});
    if (it == border_edges_.end()) return p;
    const gp_Pnt q(p.x, p.y, p.z);
    double best = -1;
    Vec3 out = p;
    for (const TopoDS_Edge& e : it->second) {
      BRepAdaptor_Curve curve(e);
      Extrema_ExtPC ext(q, curve);
      if (!ext.IsDone()) continue;
      for (int i = 1; i <= ext.NbExt(); ++i) {
        if (!ext.IsMin(i)) continue;
        const double d = ext.SquareDistance(i);
        if (best < 0 || d < best) best = d, out = to_vec(ext.Point(i).Value());
      }
    }
    return out;
  }

  const CadModel::Impl& cad_;
  std::map<std::pair<int, int>, std::vector<TopoDS_Edge>> border_edges_;
  mutable std::map<int, FaceProjector> projectors_;
  mutable std::map<int, bool> plane_;
};

}  // namespace

std::unique_ptr<SurfaceGeometry> CadModel::geometry() const { return std::make_unique<CadGeometry>(*impl_); }

std::vector<GeometryCheck> CadModel::volume_checks(const Mesh& mesh) const {
  const std::vector<double> volume = region_volumes(mesh);
  std::vector<GeometryCheck> out;
  for (size_t s = 0; s < impl_->solids.size(); ++s) {
    GProp_GProps props;
    BRepGProp::VolumeProperties(impl_->solids[s], props);
    const int n = impl_->solid_number[s];
    out.push_back({"Solid" + std::to_string(n), props.Mass(), n < static_cast<int>(volume.size()) ? volume[n] : 0.0});
  }
  return out;
}

std::vector<GeometryCheck> CadModel::area_checks(const Mesh& mesh) const {
  std::map<int, double> area;
  const bool curved = mesh.triangle_mid.size() == mesh.triangles.size() && !mesh.triangles.empty();
  for (size_t i = 0; i < mesh.triangles.size(); ++i) {
    const Triangle& t = mesh.triangles[i];
    if (curved) {
      std::array<Vec3, 6> x;
      for (int k = 0; k < 3; ++k) x[k] = mesh.points[t.v[k]], x[3 + k] = mesh.points[mesh.triangle_mid[i][k]];
      area[t.face] += quadratic_triangle_area(x);
    } else {
      area[t.face] += 0.5 * norm(cross(mesh.points[t.v[1]] - mesh.points[t.v[0]], mesh.points[t.v[2]] - mesh.points[t.v[0]]));
    }
  }
  std::vector<GeometryCheck> out;
  for (size_t f = 0; f < impl_->faces.size(); ++f) {
    GProp_GProps props;
    BRepGProp::SurfaceProperties(impl_->faces[f], props);
    const int n = impl_->face_number[f];
    out.push_back({"Face" + std::to_string(n), props.Mass(), area.count(n) ? area[n] : 0.0});
  }
  return out;
}

}  // namespace vd::cad
