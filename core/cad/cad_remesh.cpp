// The inside of each face meshed anew: a Delaunay refinement (CGAL's 2D
// mesher, smallest angle 20.7 deg) in a chart of the face's (u, v) where
// angles are those on the face (or nearly), the border nodes kept as they are
// so that the faces still share their edges' discretisation.
//
// Why: OpenCASCADE tessellates a face from its border nodes and the chord
// height, and the splits and flips after it cannot undo its fans: half the
// crankshaft's triangles have a corner under 20 deg. The volume mesh's
// smallest angles sit on such triangles. The same volume mesher on Gmsh's
// surface mesh of three corpus parts reached 4.65 / 6.60 / 10.07 deg where
// the refined tessellation gave 3.79 / 2.85 / 4.28.
//
// The charts (FaceChart): planes, cylinders and cones unroll onto the plane
// without stretching (a cone into a sector of a disc); spheres (Mercator) and
// tori map conformally, lengths scaled by a factor that varies smoothly over
// the face, so a small round triangle in the chart is round on the face and
// the size bound is divided by that factor. Other faces (B-splines, surfaces
// of revolution and extrusion) get an affine chart, an isometry at the
// face's middle only: their new mesh is kept when its smallest corner on the
// face is larger than the old one's and it lies as close to the face.
#include <CGAL/Constrained_Delaunay_triangulation_2.h>
#include <CGAL/Delaunay_mesh_face_base_2.h>
#include <CGAL/Delaunay_mesh_size_criteria_2.h>
#include <CGAL/Delaunay_mesh_vertex_base_2.h>
#include <CGAL/Delaunay_mesher_2.h>
#include <CGAL/Delaunay_mesher_no_edge_refinement_2.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Triangulation_vertex_base_with_info_2.h>

#include <BRepAdaptor_Surface.hxx>
#include <ElSLib.hxx>
#include <GeomAbs_SurfaceType.hxx>
#include <Standard_Failure.hxx>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <exception>
#include <functional>
#include <limits>
#include <map>
#include <memory>
#include <set>
#include <unordered_map>
#include <unordered_set>

#include "cad/cad_impl.h"
#include "mesh/parallel.h"
#include "surface/edge_map.h"
#include "surface/face_patches.h"

namespace vd::cad {
namespace {

using K = CGAL::Exact_predicates_inexact_constructions_kernel;
struct VertexId {
  int id = -1;  // the surface's vertex; -1 for one the mesher added
};
using Vb = CGAL::Delaunay_mesh_vertex_base_2<K, CGAL::Triangulation_vertex_base_with_info_2<VertexId, K>>;
using Fb = CGAL::Delaunay_mesh_face_base_2<K>;
using Tds = CGAL::Triangulation_data_structure_2<Vb, Fb>;
using Cdt = CGAL::Constrained_Delaunay_triangulation_2<K, Tds, CGAL::Exact_predicates_tag>;
using Point2 = K::Point_2;

// CGAL's bound B on (circumradius / shortest edge)^-2 / 4: 0.125 is a
// smallest angle of 20.7 deg, the one Ruppert's refinement is sure to reach.
constexpr double kAngleBound = 0.125;
// How many times its facets a face may get (equilateral triangles of its
// longest edge against its facets): kMaxFaceGrowth while the whole surface
// would stay within kMaxSurfaceGrowth times its facets, kMaxFaceGrowthOverBudget
// when it would not. A thin cylinder at a size above its diameter asks for
// many times its strips' facets (caxif's pins), and left to its strips its
// tetrahedra are flat; a thin solid whose chord height asks for tiny edges
// everywhere (pythonocc_11752.stp: 460k -> 10.9M facets) is not remeshed.
constexpr double kMaxFaceGrowth = 50;
constexpr double kMaxFaceGrowthOverBudget = 3;
constexpr double kMaxSurfaceGrowth = 4;
// The budget is never below this many new facets: OpenCASCADE's strips on a
// thin cylinder are halved down to the size, so four times their count
// refused a pin's remesh by chance (a 6 x 200 pin: 20,650 facets asked
// against a budget of 17,776 at size 6.3 and 34,544 at 6.2), and its strips
// (corners of 2.6 deg) left 4,282 of 10,003 tetrahedra under 5 deg at the
// default size, exit 0 (2026-11-30).
constexpr double kSmallestSurfaceBudget = 200000;


// The longest chord across a radius of curvature rho for a chord height h:
// sqrt(8 rho h), and at most the chord of a kMaxArcDeg arc. A chord height
// chosen from the size can exceed a small radius, and the arc bound nothing:
// gmsh_dlr_f6.brep's Face74, a strip of a radius-4 cylinder at a chord
// height of 4.96, was crossed by single chords of 120 degrees and kept
// 86.8 % of its area (98.5 % now). On cylinders and tori only: on the
// corpus the same bound on B-spline faces and spheres (and at 90 degrees)
// changed which tessellation gmsh_simple_plane.brep meshes on, leaving two
// of its wing pieces 4.7 % over their volume, and lowered the Ventilator's
// smallest angle from 5.28 to 3.29 deg. With it on cylinders and tori the
// corpus's other files are unchanged, but the Ventilator (5.28 -> 6.93
// deg), CP_Radial (7.60 -> 10.08), SOIC-8 (15.81 -> 16.01) and the DLR-F6
// (6.50 -> 6.34; 186,153 -> 186,454 tetrahedra). Also on cones that reach
// their apex (FaceChart::longest), where the chord height bounds nothing
// near the apex (2026-12-01).
constexpr double kMaxArcDeg = 60;
// The chord of a kMaxArcDeg arc of a circle of this radius.
double max_arc_chord(double radius) { return 2 * radius * std::sin(0.5 * kMaxArcDeg * M_PI / 180); }
double chord_for(double rho, double deflection) {
  return std::min(std::sqrt(8 * rho * deflection), max_arc_chord(rho));
}

// A face's (u, v) mapped to a plane whose angles are those on the face.
// Lengths on the face are lengths in the plane times stretch(p); the longest
// edge allowed on the face at p is longest(p), so that the refinement's size
// bound in the plane is longest(p) / stretch(p).
class FaceChart {
 public:
  // False when no chart is made (a degenerate surface). `corners`: the
  // (u, v) of the face's facet corners.
  bool make(const TopoDS_Face& face, double size, double deflection, const std::vector<gp_Pnt2d>& corners);
  // True where angles in the chart are those on the face; false for the
  // affine chart of other surfaces, whose meshes are kept only when rounder.
  bool keeps_angles() const { return kind_ != Kind::kAffine; }
  double deflection() const { return deflection_; }
  // The face's point at a point of the chart.
  gp_Pnt value(const Point2& p) const {
    const gp_Pnt2d uv = to_uv(p);
    return surface_->Value(uv.X(), uv.Y());
  }

  Point2 to_plane(const gp_Pnt2d& uv) const {
    const double u = uv.X(), v = uv.Y();
    switch (kind_) {
      case Kind::kScaled:
        return {scale_u_ * u, v};
      case Kind::kCone: {
        const double rho = cone_apex_distance(v), theta = u * sin_;
        return {rho * std::cos(theta), rho * std::sin(theta)};
      }
      case Kind::kSphere:
        return {radius_ * u, radius_ * std::atanh(std::sin(v))};
      case Kind::kStereographic: {
        const gp_Vec w(sphere_.Location(), ElSLib::Value(u, v, sphere_));
        const double k = radius_ / (radius_ - w.Dot(from_));
        return {k * w.Dot(e1_), k * w.Dot(e2_)};
      }
      case Kind::kTorus:
        return {major_ * u, major_ * torus_w(v)};
      case Kind::kAffine:
        return {a_ * (u - u0_) + b_ * (v - v0_), c_ * (v - v0_)};
    }
    return {};
  }

  gp_Pnt2d to_uv(const Point2& p) const {
    switch (kind_) {
      case Kind::kScaled:
        return {p.x() / scale_u_, p.y()};
      case Kind::kCone: {
        // The angle unwrapped next to the face's middle: a cone face spans
        // 2 pi sin(semi-angle) < 2 pi of it.
        const double theta = theta_mid_ + std::remainder(std::atan2(p.y(), p.x()) - theta_mid_, 2 * M_PI);
        const double rho = std::hypot(p.x(), p.y());
        return {theta / sin_, sign_ * rho - apex_v_};
      }
      case Kind::kSphere:
        return {p.x() / radius_, std::atan(std::sinh(p.y() / radius_))};
      case Kind::kStereographic: {
        // u is any at a pole and jumps by 2 pi across the seam: tidy()
        // makes each facet's corners agree.
        const double r2 = radius_ * radius_, rho2 = p.x() * p.x() + p.y() * p.y();
        const gp_Vec w = (2 * r2 * (p.x() * e1_ + p.y() * e2_) + radius_ * (rho2 - r2) * from_) / (r2 + rho2);
        double u = 0, v = 0;
        ElSLib::Parameters(sphere_, sphere_.Location().Translated(w), u, v);
        return {u, v};
      }
      case Kind::kTorus:
        return {p.x() / major_, torus_v(p.y() / major_)};
      case Kind::kAffine: {
        const double dv = p.y() / c_;
        return {u0_ + (p.x() - b_ * dv) / a_, v0_ + dv};
      }
    }
    return {};
  }

  double stretch(const Point2& p) const {
    switch (kind_) {
      case Kind::kScaled:
      case Kind::kCone:
        return 1;
      case Kind::kSphere:
        return 1 / std::cosh(p.y() / radius_);
      case Kind::kStereographic: {
        const double r2 = radius_ * radius_;
        return 2 * r2 / (r2 + p.x() * p.x() + p.y() * p.y());
      }
      case Kind::kTorus:
        return (major_ + minor_ * std::cos(torus_v(p.y() / major_))) / major_;
      case Kind::kAffine:
        // The area's scale, as if the surface's metric stayed isotropic.
        return std::sqrt(std::sqrt(std::max(metric_determinant(to_uv(p)), 1e-300) / det0_));
    }
    return 1;
  }

  double longest(const Point2& p) const {
    if (kind_ != Kind::kCone || !(deflection_ > 0)) return longest_;
    // Curvature cos(semi-angle) / r at distance r from the axis; towards an
    // apex no more than 10 times finer than at the face's widest circle.
    // (10 times finer than the size until 2026-11-28: on a cone smaller
    // than a tenth of the size, the chord height bound nothing, and
    // gmsh_simple_plane.brep's nose cones, 3 mm across at size 194 mm, kept
    // facets 1.5 mm long at their apex, 2.2e-5 off the cone: their solids
    // stayed 0.62 % short of their volume whatever the chord height.)
    // On a cone that reaches its apex, arcs of kMaxArcDeg at most: there
    // the chord height's chord outgrows the radius, and the quarter cone at
    // gmsh_simple_plane.brep's nose tip (0.28 mm across) was crossed by
    // single 90 deg chords at every chord height the volume rounds tried,
    // 4.8 % short of its area and its solids 0.70 % short of their volume
    // (0.39 % with it, and the rounds' held-solid check of
    // cad_model.h). On every cone (tried), the nose's neighbour got a cap
    // fold halved by three rounds down to 5 um, and a 0.09 deg tetrahedron.
    // Not on three quarters of a turn or more round the apex: on a whole
    // turn the bound took the apex's fan down to two triangles, half a turn
    // each, a fold (folds_on_face), and the face kept OpenCASCADE's needles
    // (a pointy cone's smallest dihedral angle 2.41 deg instead of over 10).
    const double r = std::hypot(p.x(), p.y()) * sin_;
    double chord = std::sqrt(8 * r * deflection_ / cos_);
    if (pointed_) chord = std::min(chord, max_arc_chord(r));
    return std::min(longest_, std::max(cone_floor_, chord));
  }
  // A chart can take the face: no corner at a point a sphere's chart sends
  // to infinity (Mercator's poles, the stereographic projection's centre).
  bool covers(const gp_Pnt2d& uv) const {
    switch (kind_) {
      case Kind::kSphere:
        return std::cos(uv.Y()) > 1e-6;
      case Kind::kStereographic:
        return gp_Vec(sphere_.Location(), ElSLib::Value(uv.X(), uv.Y(), sphere_)).Dot(from_) < kFarFromCentre * radius_;
      default:
        return true;
    }
  }
  // Is uv where a whole segment of (u, v) goes to one point of the chart (a
  // cone's apex, a sphere's pole)? A vertex there is a singular one of the
  // tessellation, which the chart can take.
  bool at_a_point(const gp_Pnt2d& uv) const {
    switch (kind_) {
      case Kind::kCone:
        return std::abs(cone_apex_distance(uv.Y())) <= 1e-9 * longest_;
      case Kind::kStereographic:
        return std::cos(uv.Y()) <= 1e-6;
      default:
        return false;
    }
  }
  // Does the chart know every point where the face's (u, v) degenerates
  // (a cone's apex, a sphere's poles) and take it as one point? Then a
  // singular vertex of the tessellation is either such a point or, singular
  // on another face only (an ellipsoid's pole on a plane's border), a
  // regular point here. Affine charts do not know.
  bool knows_its_singular_points() const { return kind_ != Kind::kAffine; }
  // A new facet's corners made to agree: on a sphere u unwrapped next to
  // the first corner's; at an apex or pole u taken as the other corners'
  // mean (any u is that point; the mean keeps mid-points in the facet).
  void tidy(std::array<gp_Pnt2d, 3>& uv) const {
    if (kind_ != Kind::kCone && kind_ != Kind::kStereographic) return;
    int first = -1, regular = 0;
    double sum = 0;
    for (int i = 0; i < 3; ++i) {
      if (at_a_point(uv[i])) continue;
      if (first < 0) first = i;
      if (kind_ == Kind::kStereographic)
        uv[i].SetX(uv[first].X() + std::remainder(uv[i].X() - uv[first].X(), 2 * M_PI));
      sum += uv[i].X();
      ++regular;
    }
    if (regular == 0) return;
    for (int i = 0; i < 3; ++i)
      if (at_a_point(uv[i])) uv[i].SetX(sum / regular);
  }

 private:
  enum class Kind { kScaled, kCone, kSphere, kStereographic, kTorus, kAffine };
  // The stereographic projection's centre stays this far from every corner
  // (cos 5 deg of arc): near it the chart's lengths blow up.
  static constexpr double kFarFromCentre = 0.996;

  bool make_affine(const std::vector<gp_Pnt2d>& corners, double deflection);
  // The largest principal curvature (absolute) at uv, from the two
  // fundamental forms: |H| + sqrt(H^2 - K).
  double largest_curvature(const gp_Pnt2d& uv) const {
    gp_Pnt p;
    gp_Vec su, sv, suu, svv, suv;
    surface_->D2(uv.X(), uv.Y(), p, su, sv, suu, svv, suv);
    const gp_Vec cross = su.Crossed(sv);
    const double area2 = cross.SquareMagnitude();
    if (!(area2 > 0)) return 0;
    const gp_Vec n = cross / std::sqrt(area2);
    const double e = su.SquareMagnitude(), f = su.Dot(sv), g = sv.SquareMagnitude();
    const double l = suu.Dot(n), m = suv.Dot(n), nn = svv.Dot(n);
    const double gauss = (l * nn - m * m) / area2, mean = (e * nn - 2 * f * m + g * l) / (2 * area2);
    return std::abs(mean) + std::sqrt(std::max(0.0, mean * mean - gauss));
  }
  // E G - F^2 of the first fundamental form at uv.
  double metric_determinant(const gp_Pnt2d& uv) const {
    gp_Pnt p;
    gp_Vec du, dv;
    surface_->D1(uv.X(), uv.Y(), p, du, dv);
    return du.CrossSquareMagnitude(dv);
  }

  // On a cone (OpenCASCADE: radius R + v sin a at height v cos a), the
  // distance from the apex along the line through the point.
  double cone_apex_distance(double v) const { return sign_ * (v + apex_v_); }
  // On a torus (radius R + r cos v about the axis), the conformal height
  // w(v) = integral of r / (R + r cos t) dt, continuous through every turn
  // of v; the chart is (R u, R w).
  double torus_w(double v) const {
    const double h = 0.5 * v, n = std::round(h / M_PI), rest = h - n * M_PI;
    return w_scale_ * (n * M_PI + std::atan2(k_ * std::sin(rest), std::cos(rest)));
  }
  double torus_v(double w) const {
    const double phi = w / w_scale_, n = std::round(phi / M_PI), rest = phi - n * M_PI;
    return 2 * (n * M_PI + std::atan2(std::sin(rest), k_ * std::cos(rest)));
  }

  Kind kind_ = Kind::kScaled;
  double longest_ = 0, deflection_ = 0;
  double scale_u_ = 1;                                              // plane, cylinder
  double sin_ = 1, cos_ = 1, sign_ = 1, apex_v_ = 0, theta_mid_ = 0, cone_floor_ = 0;  // cone
  bool pointed_ = false;  // reaches its apex, under 3/4 of a turn round it: arcs of kMaxArcDeg at most
  double radius_ = 1;                                               // sphere
  gp_Sphere sphere_;                                                // stereographic: projected
  gp_Vec from_, e1_, e2_;  // from the sphere's point centre + R from_ onto the plane of e1_, e2_
  double major_ = 1, minor_ = 0, k_ = 1, w_scale_ = 1;              // torus
  double u0_ = 0, v0_ = 0, a_ = 1, b_ = 0, c_ = 1, det0_ = 1;       // affine
  std::shared_ptr<BRepAdaptor_Surface> surface_;
};

// The longest edge for a face: the size, and on a curved face the chord
// that keeps the face's chord height (deflection).
bool FaceChart::make(const TopoDS_Face& face, double size, double deflection, const std::vector<gp_Pnt2d>& corners) {
  if (corners.empty()) return false;
  surface_ = std::make_shared<BRepAdaptor_Surface>(face);
  const BRepAdaptor_Surface& surface = *surface_;
  longest_ = size;
  deflection_ = deflection;
  auto chord = [&](double radius) {
    if (deflection > 0) longest_ = std::min(longest_, std::sqrt(8 * radius * deflection));
  };
  auto chord_within_arc = [&](double radius) {
    if (deflection > 0) longest_ = std::min(longest_, chord_for(radius, deflection));
  };
  switch (surface.GetType()) {
    case GeomAbs_Plane:
      kind_ = Kind::kScaled;
      scale_u_ = 1;
      return true;
    case GeomAbs_Cylinder: {
      const double r = surface.Cylinder().Radius();
      if (!(r > 0)) return false;
      kind_ = Kind::kScaled;
      scale_u_ = r;
      // The chord height, and arcs of at most kMaxArcDeg (chord_for): the
      // angular deflection (20 deg by default) in every direction
      // (edges of 2 R sin(angle / 2)) made tiny triangles on small
      // cylinders: the pump housing 60k -> 240k tetrahedra, 126k with the
      // growth guard below, and its smallest angle 0.95 deg where the
      // chord height alone gives 117k and 10.00 deg. The angle still
      // spaces the nodes on the border arcs, and the volume tolerance
      // makes the chord height smaller where a volume is off.
      chord_within_arc(r);
      return true;
    }
    case GeomAbs_Cone: {
      const gp_Cone cone = surface.Cone();
      const double a = cone.SemiAngle();
      if (!(std::abs(std::sin(a)) > 1e-6) || !(std::cos(a) > 1e-6)) return false;
      kind_ = Kind::kCone;
      sin_ = std::abs(std::sin(a));
      cos_ = std::cos(a);
      sign_ = std::sin(a) > 0 ? 1 : -1;
      apex_v_ = cone.RefRadius() / std::sin(a);
      // The angle is unwrapped next to the face's middle.
      double lo = corners[0].X(), hi = lo;
      for (const gp_Pnt2d& c : corners) lo = std::min(lo, c.X()), hi = std::max(hi, c.X());
      theta_mid_ = 0.5 * (lo + hi) * sin_;
      double widest = 0;  // distance from the axis
      double nearest = std::numeric_limits<double>::infinity();
      for (const gp_Pnt2d& c : corners) {
        const double r = std::abs(cone_apex_distance(c.Y())) * sin_;
        widest = std::max(widest, r);
        nearest = std::min(nearest, r);
      }
      pointed_ = nearest <= 1e-6 * widest && hi - lo < 1.5 * M_PI;
      // (Without a chord height, longest(p) is longest_ and the floor unused.)
      cone_floor_ = 0.1 * std::min(longest_, std::sqrt(8 * widest * std::max(deflection, 0.0) / cos_));
      return true;  // its chord varies with the radius: longest(p)
    }
    case GeomAbs_Sphere: {
      const double r = surface.Sphere().Radius();
      if (!(r > 0)) return false;
      radius_ = r;
      chord(r);
      // Mercator without a pole. With one or both, the stereographic
      // projection (conformal too, stretch 2 R^2 / (R^2 + rho^2)) from the
      // point opposite the corners' mean direction: a polar cap's other
      // pole, a hole's middle. It must stay clear of every corner.
      bool pole = false;
      for (const gp_Pnt2d& c : corners) pole |= std::cos(c.Y()) <= 1e-6;
      if (!pole) {
        kind_ = Kind::kSphere;
        return true;
      }
      kind_ = Kind::kStereographic;
      sphere_ = surface.Sphere();
      gp_Vec mean(0, 0, 0);
      for (const gp_Pnt2d& c : corners)
        mean += gp_Vec(sphere_.Location(), ElSLib::Value(c.X(), c.Y(), sphere_)) / r;
      if (!(mean.Magnitude() > 0.05 * static_cast<double>(corners.size()))) return false;
      from_ = -mean.Normalized();
      e1_ = std::abs(from_.X()) < 0.9 ? gp_Vec(1, 0, 0) : gp_Vec(0, 1, 0);
      e1_ = (e1_ - e1_.Dot(from_) * from_).Normalized();
      e2_ = from_.Crossed(e1_);
      for (const gp_Pnt2d& c : corners)
        if (!covers(c)) return false;
      return true;
    }
    case GeomAbs_Torus: {
      const gp_Torus torus = surface.Torus();
      const double big = torus.MajorRadius(), small = torus.MinorRadius();
      if (!(small > 0) || !(big > 1.001 * small)) return false;  // a spindle torus folds
      kind_ = Kind::kTorus;
      major_ = big;
      minor_ = small;
      k_ = std::sqrt((big - small) / (big + small));
      w_scale_ = 2 * small / std::sqrt(big * big - small * small);
      chord_within_arc(small);  // the curvature 1 / r across the tube is the larger one
      return true;
    }
    default:
      return make_affine(corners, deflection);
  }
}

// Any other surface (B-splines, surfaces of revolution or extrusion): (u, v)
// sheared and scaled so that at the middle of the face's corners the chart
// is an isometry (the Cholesky factor of the first fundamental form there).
// Away from the middle the metric drifts; stretch() follows its area scale,
// and the mesh is kept only when rounder than the old one on the face. The
// chord is that of the largest principal curvature at the corners.
bool FaceChart::make_affine(const std::vector<gp_Pnt2d>& corners, double deflection) {
  kind_ = Kind::kAffine;
  double lo_u = corners[0].X(), hi_u = lo_u, lo_v = corners[0].Y(), hi_v = lo_v;
  for (const gp_Pnt2d& c : corners) {
    lo_u = std::min(lo_u, c.X()), hi_u = std::max(hi_u, c.X());
    lo_v = std::min(lo_v, c.Y()), hi_v = std::max(hi_v, c.Y());
  }
  u0_ = 0.5 * (lo_u + hi_u);
  v0_ = 0.5 * (lo_v + hi_v);
  gp_Pnt p;
  gp_Vec du, dv;
  surface_->D1(u0_, v0_, p, du, dv);
  const double e = du.SquareMagnitude(), f = du.Dot(dv), g = dv.SquareMagnitude();
  det0_ = e * g - f * f;
  if (!(e > 0) || !(det0_ > 1e-12 * e * g)) return false;  // degenerate at the middle
  a_ = std::sqrt(e);
  b_ = f / a_;
  c_ = std::sqrt(det0_ / e);
  if (deflection > 0) {
    const size_t step = std::max<size_t>(1, corners.size() / 256);
    double curvature = 0;
    for (size_t k = 0; k < corners.size(); k += step) curvature = std::max(curvature, largest_curvature(corners[k]));
    if (curvature > 0) longest_ = std::min(longest_, std::sqrt(8 * deflection / curvature));
  }
  return true;
}

// The border nodes where a face's own angle is sharp (find_sharp_corners).
using SharpCorners = std::vector<Cdt::Vertex_handle>;

// CGAL's size criteria with the size bound of the chart's point: CGAL's
// quality (the squared sine of the smallest angle, and the longest edge over
// the size bound), the bound taken at the triangle's centroid.
class ChartCriteria : public CGAL::Delaunay_mesh_size_criteria_2<Cdt> {
 public:
  using Base = CGAL::Delaunay_mesh_size_criteria_2<Cdt>;
  ChartCriteria(const FaceChart& chart, const SharpCorners& sharp)
      : Base(kAngleBound, 1.0), chart_(&chart), sharp_(&sharp) {}

  class Is_bad : public Base::Is_bad {
   public:
    Is_bad(double bound, const FaceChart& chart, const SharpCorners& sharp, const K& traits)
        : Base::Is_bad(bound, 1.0, traits), chart_(&chart), sharp_(&sharp) {}
    using Base::Is_bad::operator();
    CGAL::Mesh_2::Face_badness operator()(const Cdt::Face_handle& f, Quality& q) const {
      const Point2 &a = f->vertex(0)->point(), &b = f->vertex(1)->point(), &c = f->vertex(2)->point();
      std::array<double, 3> sq = {CGAL::squared_distance(b, c), CGAL::squared_distance(c, a),
                                  CGAL::squared_distance(a, b)};
      std::sort(sq.begin(), sq.end());
      const Point2 centroid = CGAL::centroid(a, b, c);
      const double bound = chart_->longest(centroid) / chart_->stretch(centroid);
      q.second = sq[2] / (bound * bound);
      if (q.size() > 1) {
        q.first = 1;
        return CGAL::Mesh_2::IMPERATIVELY_BAD;
      }
      const double area = 2 * this->traits.compute_area_2_object()(a, b, c);
      q.first = area * area / (sq[2] * sq[1]);
      if (q.sine() >= this->B) return CGAL::Mesh_2::NOT_BAD;
      // A triangle whose smallest corner is a sharp corner of the face
      // keeps it whatever is inserted: Ruppert's rule for small input
      // angles. Refined anyway, it sent CGAL's mesher splitting the border
      // in shells towards the corner (caxif_as1-oc-214.stp, where a
      // cylinder stands on a block tangent to its edge: chords of 0.04
      // beside 0.2 on the other side, caps of 179.8 deg on the plane, and
      // 0.32 deg tetrahedra on them).
      for (int i = 0; i < 3; ++i) {
        const Cdt::Vertex_handle v = f->vertex(i);
        if (std::find(sharp_->begin(), sharp_->end(), v) == sharp_->end()) continue;
        const double opposite = CGAL::squared_distance(f->vertex(f->ccw(i))->point(), f->vertex(f->cw(i))->point());
        if (opposite <= sq[0]) return CGAL::Mesh_2::NOT_BAD;
      }
      return CGAL::Mesh_2::BAD;
    }

   private:
    const FaceChart* chart_;
    const SharpCorners* sharp_;
  };
  Is_bad is_bad_object() const { return Is_bad(this->bound(), *chart_, *sharp_, this->traits); }

 private:
  const FaceChart* chart_;
  const SharpCorners* sharp_;
};

using Mesher = CGAL::Delaunay_mesher_no_edge_refinement_2<Cdt, ChartCriteria>;
using FullMesher = CGAL::Delaunay_mesher_2<Cdt, ChartCriteria>;  // splits the border too

// The end of edge e that is not v.
Cdt::Vertex_handle other_end(const Cdt::Edge& e, const Cdt::Vertex_handle& v) {
  const auto& [f, i] = e;
  return f->vertex(f->ccw(i)) == v ? f->vertex(f->cw(i)) : f->vertex(f->ccw(i));
}

// The nodes of a border piece from its node `from` on: along the
// constraint through the mesher's new nodes (id -1) up to the next old node.
std::vector<Cdt::Vertex_handle> walk(const Cdt& cdt, const Cdt::Vertex_handle& from,
                                     const Cdt::Vertex_handle& next_node) {
  std::vector<Cdt::Vertex_handle> nodes{next_node};
  Cdt::Vertex_handle previous = from;
  while (nodes.back()->info().id == -1 && nodes.size() < (1u << 20)) {
    const Cdt::Vertex_handle at = nodes.back();
    Cdt::Vertex_handle next;
    auto c = cdt.incident_edges(at), done = c;
    do {
      if (cdt.is_infinite(*c) || !cdt.is_constrained(*c)) continue;
      const Cdt::Vertex_handle other = other_end(*c, at);
      if (other != previous) next = other;
    } while (++c != done);
    if (next == Cdt::Vertex_handle()) break;
    previous = at;
    nodes.push_back(next);
  }
  return nodes;
}

double area2(const Point2& a, const Point2& b, const Point2& c) {
  return (b.x() - a.x()) * (c.y() - a.y()) - (b.y() - a.y()) * (c.x() - a.x());
}

// Faces inside the border: an odd number of constraints crossed from the
// infinite face (holes are even).
void mark_inside(Cdt& cdt) {
  for (auto f = cdt.all_faces_begin(); f != cdt.all_faces_end(); ++f) f->set_in_domain(false);
  std::map<Cdt::Face_handle, int> depth;
  std::vector<Cdt::Face_handle> layer{cdt.infinite_face()};
  depth[cdt.infinite_face()] = 0;
  for (int d = 0; !layer.empty(); ++d) {
    std::vector<Cdt::Face_handle> across;  // behind a constraint: the next layer
    for (size_t k = 0; k < layer.size(); ++k) {
      const Cdt::Face_handle f = layer[k];
      f->set_in_domain(d % 2 == 1);
      for (int i = 0; i < 3; ++i) {
        const Cdt::Face_handle n = f->neighbor(i);
        if (depth.count(n)) continue;
        if (cdt.is_constrained({f, i})) {
          across.push_back(n);
        } else {
          depth[n] = d;
          layer.push_back(n);
        }
      }
    }
    layer.clear();
    for (const Cdt::Face_handle n : across)
      if (!depth.count(n)) {
        depth[n] = d + 1;
        layer.push_back(n);
      }
  }
}

// A face's angle at a border node under this is sharp: the 20 deg under
// which the issue excuses slivers, and about the 20.7 deg Ruppert's
// refinement reaches. 10 changed 4 files of the CAD corpus by a few
// tetrahedra under 10 deg (the Block 384k -> 395k tetrahedra).
constexpr double kSharpCornerDeg = 20;
// At such a corner, the first node added on a border piece without planned
// nodes: its distance over the other border's first node's
// (equal_first_nodes_at_sharp_corners).
constexpr double kStaggeredFirstNode = 1.3;

// The border nodes where the face's angle (the sum of its triangles'
// corners there) is sharp.
SharpCorners find_sharp_corners(const Cdt& cdt) {
  const double limit = kSharpCornerDeg * M_PI / 180;
  SharpCorners corners;
  for (auto v = cdt.finite_vertices_begin(); v != cdt.finite_vertices_end(); ++v) {
    double angle = 0;
    bool on_border = false;
    auto f = cdt.incident_faces(v), done = f;
    do {
      if (cdt.is_infinite(f) || !f->is_in_domain()) {
        on_border = true;
        continue;
      }
      const int i = f->index(v);
      const Point2 &p = v->point(), &q = f->vertex(f->ccw(i))->point(), &r = f->vertex(f->cw(i))->point();
      const double ux = q.x() - p.x(), uy = q.y() - p.y(), wx = r.x() - p.x(), wy = r.y() - p.y();
      angle += std::atan2(std::abs(ux * wy - uy * wx), ux * wx + uy * wy);
    } while (++f != done);
    if (on_border && angle > 0 && angle < limit) corners.push_back(v);
  }
  return corners;
}

// One face's border in its chart: the facet edges on CAD edges (a seam
// twice, once per side), in a constrained Delaunay triangulation, the
// inside marked.
struct FaceBorder {
  Cdt cdt;
  std::vector<std::pair<Cdt::Vertex_handle, Cdt::Vertex_handle>> segments;
  int sign = 0;              // of the facets' orientation in the plane
  double area = 0;           // twice the facets' area in the plane
  double expected_facets = 0;  // about how many the refinement makes (the facets' areas over their sizes')
  SharpCorners sharp_corners;
};

class FaceRemesher {
 public:
  FaceRemesher(const CadModel::Impl& cad, CadSurface& s, double growth_limit, const std::vector<char>& past_limit)
      : cad_(cad), s_(s), growth_limit_(growth_limit), past_limit_(past_limit), edges_(s.mesh.triangles) {}

  // False when the facets do not make a clean domain in the plane: folded,
  // a border without CAD parameters, a singular vertex (a pole, an apex)
  // the chart cannot place, crossing segments. `piece`: the facets are a
  // part of the face (ChartedFace), and its edges with the rest of the face,
  // the cut, are a border too, kept as they are.
  bool border(int fi, const std::vector<int>& facets, const FaceChart& chart, FaceBorder& out,
              bool piece) const {
    const Mesh& m = s_.mesh;
    std::unordered_set<int> member;
    if (piece) member.insert(facets.begin(), facets.end());
    std::vector<std::array<Point2, 2>> points;
    std::vector<std::array<int, 2>> ids;
    for (int f : facets) {
      const Triangle& t = m.triangles[f];
      std::array<Point2, 3> p;
      for (int i = 0; i < 3; ++i) {
        if ((s_.singular.count(t.v[i]) && !chart.knows_its_singular_points()) || !chart.covers(s_.uv[f][i]))
          return false;
        p[i] = chart.to_plane(s_.uv[f][i]);
      }
      const double a = area2(p[0], p[1], p[2]);
      const int sg = a > 0 ? 1 : a < 0 ? -1 : 0;
      if (sg == 0 || (out.sign != 0 && sg != out.sign)) return false;  // folded in (u, v)
      out.sign = sg;
      out.area += std::abs(a);
      const Point2 centroid = CGAL::centroid(p[0], p[1], p[2]);
      const double stretch = chart.stretch(centroid);
      out.expected_facets += new_facets(0.5 * std::abs(a) * stretch * stretch, chart.longest(centroid));
      for (int i = 0; i < 3; ++i) {
        const int a_id = t.v[i], b_id = t.v[(i + 1) % 3];
        const std::uint64_t key = edge_key(a_id, b_id);
        const std::vector<int> around = edges_.facets(key);
        bool on_face = around.size() == 2, inner = on_face;
        for (int g : around) {
          on_face &= s_.facet_face[g] == fi;
          inner &= s_.facet_face[g] == fi && (!piece || member.count(g));
        }
        if (s_.edge_spans.count(key) || (on_face && !inner)) {
          points.push_back({p[i], p[(i + 1) % 3]});
          ids.push_back({a_id, b_id});
        } else if (!inner) {
          return false;  // a border without CAD parameters: leave the face
        }
      }
    }
    if (points.empty()) return false;
    // The same node seen from two facets: within a billionth of the face's
    // span in the plane (a seam's two sides are a period apart).
    double lo_x = points[0][0].x(), hi_x = lo_x, lo_y = points[0][0].y(), hi_y = lo_y;
    for (const auto& sgm : points) {
      lo_x = std::min(lo_x, sgm[0].x()), hi_x = std::max(hi_x, sgm[0].x());
      lo_y = std::min(lo_y, sgm[0].y()), hi_y = std::max(hi_y, sgm[0].y());
    }
    const double span = std::max(hi_x - lo_x, hi_y - lo_y);
    const double tolerance2 = 1e-18 * span * span;
    std::unordered_map<int, std::vector<Cdt::Vertex_handle>> by_id;
    auto vertex = [&](int id, const Point2& p) -> Cdt::Vertex_handle {
      auto& list = by_id[id];
      for (const auto& h : list)
        if (CGAL::squared_distance(h->point(), p) <= tolerance2) return h;
      const Cdt::Vertex_handle h = out.cdt.insert(p);
      if (h->info().id != -1 && h->info().id != id) return {};  // two nodes on one point
      h->info().id = id;
      list.push_back(h);
      return h;
    };
    try {
      // A seam whose two sides the chart puts together (a polar cap's) is
      // met from both sides: it is inside the face, not a border.
      std::map<std::pair<Cdt::Vertex_handle, Cdt::Vertex_handle>, int> seen;
      for (size_t k = 0; k < points.size(); ++k) {
        const Cdt::Vertex_handle a = vertex(ids[k][0], points[k][0]);
        const Cdt::Vertex_handle b = vertex(ids[k][1], points[k][1]);
        if (a == Cdt::Vertex_handle() || b == Cdt::Vertex_handle() || a == b) return false;
        out.segments.emplace_back(a, b);
        ++seen[std::minmax(a, b)];
      }
      out.segments.erase(std::remove_if(out.segments.begin(), out.segments.end(),
                                        [&](const auto& sg) { return seen[std::minmax(sg.first, sg.second)] > 1; }),
                         out.segments.end());
      if (out.segments.empty()) return false;
      for (const auto& [a, b] : out.segments) out.cdt.insert_constraint(a, b);
    } catch (const std::exception&) {
      return false;  // crossing segments (CGAL's exact predicates tag refuses them)
    }
    // Every segment an edge of its own: none ran through a node (the
    // insertion would have split it).
    size_t constrained = 0;
    for (auto e = out.cdt.finite_edges_begin(); e != out.cdt.finite_edges_end(); ++e)
      constrained += out.cdt.is_constrained(*e);
    if (constrained != out.segments.size()) return false;
    mark_inside(out.cdt);
    if (std::abs(domain_area(out.cdt) - out.area) > 1e-9 * out.area) return false;
    out.sharp_corners = find_sharp_corners(out.cdt);
    return true;
  }

  // Another face's nodes on a border piece join those kept so far, except
  // where one comes closer to a kept node than 0.4 of its own gaps (a
  // piece's fractions, ascending): each face gets its nodes or ones near
  // them, with no gap shorter than 0.4 of the finer. Until 2026-11-26 the
  // face with the most nodes had its way, and the other kept needles where
  // it had wanted its nodes (gmsh_part.step 5.69 -> 2.24 deg).
  static void merge_border_nodes(std::vector<double>& kept, const std::vector<double>& fresh) {
    std::vector<double> joined = kept;
    for (size_t i = 0; i < fresh.size(); ++i) {
      const double gap = std::min(fresh[i] - (i ? fresh[i - 1] : 0.0), (i + 1 < fresh.size() ? fresh[i + 1] : 1.0) - fresh[i]);
      const auto next = std::lower_bound(kept.begin(), kept.end(), fresh[i]);
      double nearest = std::min(fresh[i], 1 - fresh[i]);
      if (next != kept.end()) nearest = std::min(nearest, *next - fresh[i]);
      if (next != kept.begin()) nearest = std::min(nearest, fresh[i] - *std::prev(next));
      if (nearest >= 0.4 * gap) joined.push_back(fresh[i]);
    }
    std::sort(joined.begin(), joined.end());
    kept = std::move(joined);
  }

  // What one face asks of the plan (plan_border_splits), kept apart so that
  // faces are planned on several threads and merged in their order.
  struct BorderSplits {
    std::vector<RemeshPlan::SharpCorner> sharp_corners;
    std::vector<std::pair<std::uint64_t, std::vector<double>>> nodes;  // in the order met
    std::exception_ptr failure;  // what the planning threw, rethrown at the merge
    void merge_into(RemeshPlan& plan) const {
      plan.sharp_corners.insert(plan.sharp_corners.end(), sharp_corners.begin(), sharp_corners.end());
      for (const auto& [key, fractions] : nodes) merge_border_nodes(plan.border_nodes[key], fractions);
      if (failure) std::rethrow_exception(failure);
    }
  };

  // The border pieces the face needs split for a mesh of round triangles:
  // CGAL's mesher with segment splits is run, and where it put nodes on
  // each border piece is kept (merge_border_nodes). Reads the surface only.
  void plan_border_splits(int fi, const std::vector<int>& facets, const FaceChart& chart, bool piece,
                          BorderSplits& plan) const {
    FaceBorder b;
    if (!border(fi, facets, chart, b, piece)) return;
    // Before the face's own planning run, which may fail: a face whose new
    // mesh is not kept keeps its sharp corners too.
    for (const Cdt::Vertex_handle& v : b.sharp_corners) {
      std::vector<std::pair<int, int>> pieces;
      for (const auto& [a, end] : b.segments)
        if (a == v || end == v) pieces.emplace_back(a->info().id, end->info().id);
      if (pieces.size() != 2 || !s_.edge_spans.count(edge_key(pieces[0].first, pieces[0].second)) ||
          !s_.edge_spans.count(edge_key(pieces[1].first, pieces[1].second)))
        continue;
      RemeshPlan::SharpCorner corner{v->info().id, {}, {}};
      for (int k = 0; k < 2; ++k) {
        corner.pieces[k] = edge_key(pieces[k].first, pieces[k].second);
        corner.lengths[k] = norm(s_.mesh.points[pieces[k].first] - s_.mesh.points[pieces[k].second]);
      }
      plan.sharp_corners.push_back(corner);
    }
    if (too_many(fi, b, facets) || !refine<FullMesher>(b, chart) || !rounder(b.cdt, facets, chart)) return;
    for (const auto& [a, end] : b.segments) {
      auto circulator = b.cdt.incident_edges(a), done = circulator;
      do {
        if (b.cdt.is_infinite(*circulator) || !b.cdt.is_constrained(*circulator)) continue;
        const std::vector<Cdt::Vertex_handle> nodes = walk(b.cdt, a, other_end(*circulator, a));
        // A piece's cut is kept: only CAD borders are split.
        const std::uint64_t key = edge_key(a->info().id, end->info().id);
        if (nodes.back() != end || nodes.size() < 2 || !s_.edge_spans.count(key)) continue;
        std::vector<double> at(nodes.size());  // length walked from a
        Vec3 previous = on_face(a, chart);
        for (size_t i = 0; i < nodes.size(); ++i) {
          const Vec3 p = on_face(nodes[i], chart);
          at[i] = (i ? at[i - 1] : 0) + norm(p - previous);
          previous = p;
        }
        std::vector<double> fractions;
        for (size_t i = 0; i + 1 < nodes.size(); ++i) fractions.push_back(at[i] / at.back());
        if (a->info().id > end->info().id) {
          std::reverse(fractions.begin(), fractions.end());
          for (double& f : fractions) f = 1 - f;
        }
        plan.nodes.emplace_back(key, std::move(fractions));
      } while (++circulator != done);
    }
  }

  // A new mesh of face fi inside its border, into b; false when its facets
  // do not make a clean domain or the mesh would not cover it. Reads the
  // surface as it was (the other faces' new meshes are not in it yet), so
  // faces are meshed on several threads; replace() puts them in, in order.
  bool mesh_inside(int fi, const std::vector<int>& facets, const FaceChart& chart, bool piece, FaceBorder& b) const {
    if (!border(fi, facets, chart, b, piece) || too_many(fi, b, facets) || !refine<Mesher>(b, chart) ||
        !rounder(b.cdt, facets, chart) || folds_on_face(b.cdt, chart))
      return false;
    return std::abs(domain_area(b.cdt) - b.area) <= 1e-9 * b.area;
  }

  // Face fi's new mesh (mesh_inside) in place of its facets.
  void replace(int fi, const std::vector<int>& facets, const FaceChart& chart, FaceBorder& b, std::vector<char>& dead) {
    // The new facets, with the old facets' tags and orientation.
    const Triangle like = s_.mesh.triangles[facets.front()];
    for (auto v = b.cdt.finite_vertices_begin(); v != b.cdt.finite_vertices_end(); ++v) {
      if (v->info().id != -1) continue;
      v->info().id = static_cast<int>(s_.mesh.points.size());
      s_.mesh.points.push_back(to_vec(chart.value(v->point())));
    }
    for (int f : facets) dead[f] = 1;
    const std::array<int, 3> order = b.sign > 0 ? std::array<int, 3>{0, 1, 2} : std::array<int, 3>{0, 2, 1};
    for (auto f = b.cdt.finite_faces_begin(); f != b.cdt.finite_faces_end(); ++f) {
      if (!f->is_in_domain()) continue;
      Triangle t = like;
      std::array<gp_Pnt2d, 3> uv;
      for (int i = 0; i < 3; ++i) {
        const auto v = f->vertex(order[i]);
        t.v[i] = v->info().id;
        uv[i] = chart.to_uv(v->point());
      }
      chart.tidy(uv);
      s_.mesh.triangles.push_back(t);
      s_.uv.push_back(uv);
      s_.facet_face.push_back(fi);
      dead.push_back(0);
    }
  }

 private:
  // A node of the chart on the face: an old node where it is, a mesher's
  // new one evaluated on the CAD face.
  Vec3 on_face(const Cdt::Vertex_handle& v, const FaceChart& chart) const {
    return v->info().id >= 0 ? s_.mesh.points[v->info().id] : to_vec(chart.value(v->point()));
  }

  // Where the chart does not keep angles, is the refined mesh rounder than
  // the facets it would replace (a smallest corner on the face as large:
  // where the old smallest one sits at a sharp corner of the face the new
  // mesh keeps that triangle, and "larger" had refused every such face:
  // t20 had 11 of its 21 faces remeshed, now all, caxif 180 of 192, now
  // all), and
  // as close to the face (its triangles' centroids within the chord height,
  // or the old facets' largest distance)?
  bool rounder(const Cdt& cdt, const std::vector<int>& facets, const FaceChart& chart) const {
    if (chart.keeps_angles()) return true;
    const Mesh& m = s_.mesh;
    double corner_before = M_PI, sag_before = chart.deflection();
    for (int f : facets) {
      const Triangle& t = m.triangles[f];
      corner_before = std::min(corner_before, smallest_corner_angle(m.points, t));
      const auto& uv = s_.uv[f];
      const Point2 middle = CGAL::centroid(chart.to_plane(uv[0]), chart.to_plane(uv[1]), chart.to_plane(uv[2]));
      const Vec3 centroid = (1.0 / 3) * (m.points[t.v[0]] + m.points[t.v[1]] + m.points[t.v[2]]);
      sag_before = std::max(sag_before, norm(centroid - to_vec(chart.value(middle))));
    }
    for (auto f = cdt.finite_faces_begin(); f != cdt.finite_faces_end(); ++f) {
      if (!f->is_in_domain()) continue;
      std::array<Vec3, 3> p;
      for (int i = 0; i < 3; ++i) p[i] = on_face(f->vertex(i), chart);
      for (int i = 0; i < 3; ++i)
        if (corner_angle(p[i], p[(i + 1) % 3], p[(i + 2) % 3]) < corner_before) return false;
      const Point2 middle = CGAL::centroid(f->vertex(0)->point(), f->vertex(1)->point(), f->vertex(2)->point());
      if (norm((1.0 / 3) * (p[0] + p[1] + p[2]) - to_vec(chart.value(middle))) > sag_before) return false;
    }
    return true;
  }

  // Does a triangle of the new mesh turn over its neighbour on the face
  // (their normals on the face more than 90 deg apart)? Round in the chart,
  // a tiny triangle can fold on the face where a border node's place in the
  // chart (from its curve on the face) and on the face (from the edge's 3D
  // curve) differ by more than its width: gmsh_t20_component8.step at size
  // 1.178 had a 0.013 mm triangle of its plane Face3 folded over three
  // others at a corner where Face2 meets it at 0.26 deg, and the volume mesh
  // a tetrahedron of 0.003 deg in the fold (no sliver pass can open one
  // between two facets). The face then keeps its facets. Over 90 deg is
  // also a crease of the face itself, which the chart does not see: one face
  // of gmsh_dlr_f6.brep had pairs of new triangles at 90.0 and 90.8 deg;
  // kept as tessellated, its smallest dihedral angle went 4.87 -> 6.50 deg.
  bool folds_on_face(const Cdt& cdt, const FaceChart& chart) const {
    // Each node evaluated on the face once (a new one is a point of the CAD surface).
    std::unordered_map<const void*, Vec3> at;
    const auto place = [&](const Cdt::Vertex_handle& v) -> const Vec3& {
      const auto [it, added] = at.try_emplace(&*v);
      if (added) it->second = on_face(v, chart);
      return it->second;
    };
    const auto normal = [&](const Cdt::Face_handle& f) {
      const Vec3 a = place(f->vertex(0));
      return cross(place(f->vertex(1)) - a, place(f->vertex(2)) - a);
    };
    // Around a point where the chart's (u, v) degenerates (a cone's apex),
    // the triangles are a fan whose neighbours' normals are far apart
    // without a fold: a pointy cone's (semi-angle 26.6 deg) took three
    // triangles round in the chart, 120 deg apart around the axis and 103 deg
    // apart on the face, and the cone kept its refined tessellation, needles
    // to a split seam and tetrahedra of 0.81 deg beside it (a FreeCAD
    // tester's cone, 2026-11-30). There each triangle is held against the
    // fan's mean normal instead.
    std::unordered_map<const void*, bool> singular;
    const auto at_a_point = [&](const Cdt::Vertex_handle& v) {
      const auto [it, added] = singular.try_emplace(&*v, false);
      if (added) it->second = chart.at_a_point(chart.to_uv(v->point()));
      return it->second;
    };
    std::unordered_map<const void*, Vec3> fan_normal;  // by the singular vertex
    std::vector<std::pair<Cdt::Face_handle, const void*>> fan;
    for (auto f = cdt.finite_faces_begin(); f != cdt.finite_faces_end(); ++f) {
      if (!f->is_in_domain()) continue;
      const Vec3 n = normal(f);
      for (int i = 0; i < 3; ++i)
        if (at_a_point(f->vertex(i))) {
          { Vec3& sum = fan_normal[&*f->vertex(i)]; sum = sum + normalized(n); }
          fan.emplace_back(f, &*f->vertex(i));
        }
      for (int i = 0; i < 3; ++i) {
        const Cdt::Face_handle g = f->neighbor(i);
        // Each pair once, from the face with the smaller address.
        if (cdt.is_infinite(g) || !g->is_in_domain() || std::less<const void*>()(&*g, &*f)) continue;
        if (at_a_point(f->vertex(cdt.cw(i))) || at_a_point(f->vertex(cdt.ccw(i)))) continue;  // a fan's pair
        if (!(dot(n, normal(g)) > 0)) return true;
      }
    }
    for (const auto& [f, apex] : fan)
      if (!(dot(normal(f), fan_normal[apex]) > 0)) return true;
    return false;
  }

  // CGAL's Delaunay refinement of the marked inside; false when it throws.
  template <class RefineMesher>
  static bool refine(FaceBorder& b, const FaceChart& chart) {
    try {
      RefineMesher mesher(b.cdt, ChartCriteria(chart, b.sharp_corners));
      mesher.init(true);
      mesher.refine_mesh();
      return true;
    } catch (const std::exception&) {
      return false;
    }
  }

  // Would the face get far more facets than it has (growth_limit_ times),
  // and more than the surface's budget took?
  bool too_many(int fi, const FaceBorder& b, const std::vector<int>& facets) const {
    if (static_cast<size_t>(fi) < past_limit_.size() && past_limit_[static_cast<size_t>(fi)]) return false;
    return b.expected_facets > growth_limit_ * static_cast<double>(facets.size()) + 50;
  }

  static double domain_area(const Cdt& cdt) {
    double a = 0;
    for (auto f = cdt.finite_faces_begin(); f != cdt.finite_faces_end(); ++f)
      if (f->is_in_domain()) a += area2(f->vertex(0)->point(), f->vertex(1)->point(), f->vertex(2)->point());
    return a;
  }

  const CadModel::Impl& cad_;
  CadSurface& s_;
  double growth_limit_;
  const std::vector<char>& past_limit_;
  EdgeFacetPairs edges_;
};

// The faces, or pieces of faces, a chart is made for.
struct ChartedFace {
  int face;
  FaceChart chart;
  std::vector<int> facets;  // the face's, or the piece's
  bool piece = false;
};

// A sphere's facets on each side of its equator (by their centroids), for
// a sphere no one chart covers: a whole one has no point to project from
// (gmsh_ring.brep's, whose poles kept OpenCASCADE's fans of 30 facets with
// 10.6 deg corners, and 11.2 deg tetrahedra on them).
std::array<std::vector<int>, 2> hemispheres(const TopoDS_Face& face, const CadSurface& s,
                                            const std::vector<int>& facets) {
  const gp_Sphere sphere = BRepAdaptor_Surface(face).Sphere();
  const Vec3 centre = to_vec(sphere.Location());
  const gp_Dir d = sphere.Position().Direction();
  const Vec3 axis{d.X(), d.Y(), d.Z()};
  std::array<std::vector<int>, 2> halves;
  for (int f : facets) {
    const Triangle& t = s.mesh.triangles[f];
    const Vec3 m = (1.0 / 3) * (s.mesh.points[t.v[0]] + s.mesh.points[t.v[1]] + s.mesh.points[t.v[2]]);
    halves[dot(m - centre, axis) >= 0 ? 0 : 1].push_back(f);
  }
  return halves;
}

std::vector<ChartedFace> charted_faces(const CadModel::Impl& cad, const std::vector<std::vector<int>>& by_face,
                                       const CadSurface& s, const std::vector<double>& face_deflection,
                                       const std::vector<double>& face_size) {
  std::vector<ChartedFace> out;
  auto chart_of = [&](size_t fi, const std::vector<int>& facets, bool piece) {
    ChartedFace c{static_cast<int>(fi), {}, facets, piece};
    std::vector<gp_Pnt2d> corners;
    for (int f : facets) corners.insert(corners.end(), s.uv[f].begin(), s.uv[f].end());
    try {
      if (!c.chart.make(cad.faces[fi], face_size[fi], face_deflection[fi], corners)) return false;
    } catch (const Standard_Failure&) {
      return false;
    }
    out.push_back(std::move(c));
    return true;
  };
  for (size_t fi = 0; fi < cad.faces.size(); ++fi) {
    if (by_face[fi].empty() || chart_of(fi, by_face[fi], false)) continue;
    try {
      if (BRepAdaptor_Surface(cad.faces[fi]).GetType() != GeomAbs_Sphere) continue;
      for (const std::vector<int>& half : hemispheres(cad.faces[fi], s, by_face[fi]))
        if (!half.empty()) chart_of(fi, half, true);
    } catch (const Standard_Failure&) {
    }
  }
  return out;
}

std::vector<std::vector<int>> facets_by_face(const CadModel::Impl& cad, const CadSurface& s) {
  std::vector<std::vector<int>> by_face(cad.faces.size());
  for (size_t f = 0; f < s.mesh.triangles.size(); ++f) by_face[s.facet_face[f]].push_back(static_cast<int>(f));
  return by_face;
}

// At a sharp corner of a face the first nodes on its two borders are put as
// far from it. Otherwise the triangle at the corner has the corner's angle,
// a second one nearly as small and the third near 180 deg (a cap: the near
// node next to the chord to the far one), which Ruppert's rule for small
// angles keeps, and every tetrahedron on a cap is flat
// (gmsh_t20_component8.step: 5 deg corners where a chamfer cone meets a
// hexagon's sides, first nodes 1.50 and 2.49 away, caps of 168 deg, 1.81 deg
// tetrahedra). With the two as far, the triangle is isosceles: the corner's
// angle and two near 90 deg. At a 5 deg corner, first nodes 1.15 times as
// far as each other already make a cap of 145 deg: the far one is moved to
// the near one's distance when it is a planned node (not a tessellation
// vertex) under 1.5 times as far, and otherwise a node is added there when
// the far one is at least 1.25 times as far (a shorter gap would be a needle
// on the other face). A far node twice as far or more is left: the near one
// is there for a fine feature next to the corner, and a lone node put on
// the other face's border across from nothing makes caps there instead
// (pythonocc_Ventilator.stp: its blades' edge strips, 0.02 wide, got caps of
// 162 deg from nodes put at 0.19 where the next was 1.51 away, and the
// smallest angle went 6.89 -> 3.37 deg with the tetrahedra on them).
// Where the far piece has no planned node (its face's planning run failed,
// or put none there), the added node goes to kStaggeredFirstNode times the
// near one's distance instead (at most halfway to the far end). Equal, the
// two first nodes sit across a gap of the corner's angle, and the
// tetrahedron on the corner's triangle has about that angle at its edge into
// the solid, which sees them both (gmsh_t20_component8.step: 3.1 deg corners
// where a lens face's borders meet tangent at a hexagon's corner, 3.14 deg
// tetrahedra; staggered by 1.1, 1.2 and 1.3, 3.99 to 5.05, 7.80 and 9.40 to
// 9.45 deg over seeds 1 to 3). Before a planned node it is not done: there
// the gap to that node gets short, a needle on the other face
// (occt_MODERN_Exhaust_1.brep 303 -> 722 tetrahedra under 10 deg,
// gmsh_917_fusee.stp 4.96 -> 1.49 deg).
void equal_first_nodes_at_sharp_corners(RemeshPlan& plan) {
  for (const RemeshPlan::SharpCorner& c : plan.sharp_corners) {
    std::array<double, 2> first;
    std::array<bool, 2> from_lower;
    for (int k = 0; k < 2; ++k) {
      // Looked up, not made: a piece without nodes is not walked for splits.
      const auto it = plan.border_nodes.find(c.pieces[k]);
      from_lower[k] = edge_of_key(c.pieces[k]).first == c.corner;
      first[k] = c.lengths[k];
      if (it != plan.border_nodes.end() && !it->second.empty())
        first[k] *= from_lower[k] ? it->second.front() : 1 - it->second.back();
    }
    const int far = first[0] > first[1] ? 0 : 1;
    const double near = first[1 - far], ratio = first[far] / near;
    if (!(near > 0) || ratio <= 1.1 || ratio >= 2) continue;
    const auto it = plan.border_nodes.find(c.pieces[far]);
    const bool planned = it != plan.border_nodes.end() && !it->second.empty();
    const double target = planned ? near : std::min(kStaggeredFirstNode * near, 0.5 * (near + first[far]));
    const double at = from_lower[far] ? target / c.lengths[far] : 1 - target / c.lengths[far];
    if (planned && ratio < 1.5) {
      (from_lower[far] ? it->second.front() : it->second.back()) = at;
    } else if (ratio >= 1.25) {
      // Made only here: an empty entry would have its piece walked for splits.
      std::vector<double>& nodes = plan.border_nodes[c.pieces[far]];
      nodes.insert(std::lower_bound(nodes.begin(), nodes.end(), at), at);
    }
  }
}

}  // namespace

double new_facets(double area, double longest) { return area / (std::sqrt(3.0) / 4 * longest * longest); }

RemeshPlan plan_remeshing(const CadModel::Impl& cad, CadSurface& s, const std::vector<double>& face_deflection,
                          const std::vector<double>& face_size) {
  const auto by_face = facets_by_face(cad, s);
  const std::vector<ChartedFace> charted = charted_faces(cad, by_face, s, face_deflection, face_size);
  RemeshPlan plan;
  double total = static_cast<double>(s.mesh.triangles.size());
  std::map<int, std::pair<double, double>> past;  // face -> (facets, grown), faces past kMaxFaceGrowth
  for (const ChartedFace& c : charted) {
    double grown = 0;
    for (int f : c.facets) {
      const auto& uv = s.uv[f];
      if (!c.chart.covers(uv[0]) || !c.chart.covers(uv[1]) || !c.chart.covers(uv[2])) continue;
      const Point2 centroid =
          CGAL::centroid(c.chart.to_plane(uv[0]), c.chart.to_plane(uv[1]), c.chart.to_plane(uv[2]));
      grown += new_facets(facet_area(s.mesh.points, s.mesh.triangles[f]), c.chart.longest(centroid));
    }
    const double facets = static_cast<double>(c.facets.size());
    if (grown <= kMaxFaceGrowth * facets + 50) {
      total += grown - facets;
    } else {
      auto& [face_facets, face_grown] = past[c.face];
      face_facets += facets;
      face_grown += grown;
    }
  }
  const double budget =
      std::max(kMaxSurfaceGrowth * static_cast<double>(s.mesh.triangles.size()), kSmallestSurfaceBudget);
  plan.growth_limit = total <= budget ? kMaxFaceGrowth : kMaxFaceGrowthOverBudget;
  // Past the growth limit, while the surface stays within its budget: the
  // faces that ask for the fewest new facets first. A face's facets are
  // OpenCASCADE's, whose count on one face moves with the chord heights of
  // others: gmsh_simple_plane.brep's fuselage inside at 0.6 times its size
  // had 972 of them on one volume round and 270 on the next, which put it
  // past the limit (32,289 asked); left to OpenCASCADE's facets, its shell
  // came out 5.3 % over its volume.
  plan.past_limit.assign(cad.faces.size(), 0);
  if (total <= budget) {
    std::vector<std::pair<double, int>> asked;  // (new facets, face)
    for (const auto& [face, counts] : past) asked.emplace_back(counts.second - counts.first, face);
    std::sort(asked.begin(), asked.end());
    for (const auto& [extra, face] : asked) {
      if (total + extra > budget) break;
      total += extra;
      plan.past_limit[static_cast<size_t>(face)] = 1;
    }
  }
  const FaceRemesher remesher(cad, s, plan.growth_limit, plan.past_limit);
  // Each face planned on its own (one at a time per thread, the big ones
  // take long), merged in the faces' order: the same plan on any number of
  // threads.
  std::vector<FaceRemesher::BorderSplits> asked(charted.size());
  for_each_chunk(static_cast<long>(charted.size()), 1, [&](long, long i, long) {
    const ChartedFace& c = charted[static_cast<size_t>(i)];
    try {
      remesher.plan_border_splits(c.face, c.facets, c.chart, c.piece, asked[static_cast<size_t>(i)]);
    } catch (...) {
      asked[static_cast<size_t>(i)].failure = std::current_exception();
    }
  });
  for (const FaceRemesher::BorderSplits& a : asked) a.merge_into(plan);
  equal_first_nodes_at_sharp_corners(plan);
  return plan;
}

int remesh_faces(const CadModel::Impl& cad, CadSurface& s, const std::vector<double>& face_deflection,
                 const std::vector<double>& face_size, const RemeshPlan& plan, std::vector<char>* remeshed_out) {
  const auto by_face = facets_by_face(cad, s);
  std::vector<char> dead(s.mesh.triangles.size(), 0);
  std::set<int> remeshed;  // faces with any piece remeshed
  {
    // A piece's cut is found through the facets as they were: the other
    // piece's old facets, dead once it is remeshed, still mark it.
    // The faces meshed on several threads, each against the surface as it
    // was; put in one after another in the faces' order (new vertices are
    // numbered as they go in), so the surface is the same on any number of
    // threads. What a face's meshing threw is thrown when its turn comes,
    // after the faces before it went in, as when they were meshed in turn.
    FaceRemesher remesher(cad, s, plan.growth_limit, plan.past_limit);
    const std::vector<ChartedFace> charted = charted_faces(cad, by_face, s, face_deflection, face_size);
    std::vector<std::unique_ptr<FaceBorder>> meshes(charted.size());
    std::vector<std::exception_ptr> failures(charted.size());
    for_each_chunk(static_cast<long>(charted.size()), 1, [&](long, long i, long) {
      const ChartedFace& c = charted[static_cast<size_t>(i)];
      try {
        auto b = std::make_unique<FaceBorder>();
        if (remesher.mesh_inside(c.face, c.facets, c.chart, c.piece, *b)) meshes[static_cast<size_t>(i)] = std::move(b);
      } catch (...) {
        failures[static_cast<size_t>(i)] = std::current_exception();
      }
    });
    for (size_t i = 0; i < charted.size(); ++i) {
      if (failures[i]) std::rethrow_exception(failures[i]);
      if (!meshes[i]) continue;
      remesher.replace(charted[i].face, charted[i].facets, charted[i].chart, *meshes[i], dead);
      meshes[i].reset();
      remeshed.insert(charted[i].face);
    }
  }
  if (!remeshed.empty()) compact_surface(s, dead);
  if (remeshed_out) {
    remeshed_out->assign(cad.faces.size(), 0);
    for (const int fi : remeshed) (*remeshed_out)[fi] = 1;
  }
  return static_cast<int>(remeshed.size());
}

}  // namespace vd::cad
