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
#include <limits>
#include <map>
#include <set>
#include <tuple>
#include <sstream>

#include "cad/cad_impl.h"
#include "mesh/error.h"
#include "mesh/number_text.h"
#include "mesh/second_order.h"
#include "mesh/size_budget.h"
#include "surface/face_patches.h"
#include "volume/region_tetrahedra.h"

namespace vd::cad {
namespace {

// OpenCASCADE's volume and area to a relative precision of 1e-7. Its
// default, fixed-order integration was off by up to 0.20 % on the solids
// of gmsh_ellipses.brep, more than the tessellation's error it is meant
// to measure.
constexpr double kIntegrationPrecision = 1e-7;

double exact_volume(const TopoDS_Shape& solid) {
  GProp_GProps props;
  BRepGProp::VolumeProperties(solid, props, kIntegrationPrecision);
  return props.Mass();
}

double exact_area(const TopoDS_Shape& shape) {
  GProp_GProps props;
  BRepGProp::SurfaceProperties(shape, props, kIntegrationPrecision);
  return props.Mass();
}

// Area of faces[f], integrated once per model.
double face_area(const CadModel::Impl& cad, size_t f) {
  if (cad.face_areas.size() != cad.faces.size()) cad.face_areas.assign(cad.faces.size(), std::nan(""));
  double& a = cad.face_areas[f];
  if (std::isnan(a)) a = exact_area(cad.faces[f]);
  return a;
}

// Volume and area of solid i, integrated once per model. The area is its
// faces' (each as often as the solid uses it, as OpenCASCADE's own sum over
// a solid goes).
const std::array<double, 2>& solid_integrals(const CadModel::Impl& cad, size_t i) {
  if (cad.solid_integrals.size() != cad.solids.size())
    cad.solid_integrals.assign(cad.solids.size(), {std::nan(""), std::nan("")});
  std::array<double, 2>& v = cad.solid_integrals[i];
  if (std::isnan(v[0])) {
    double area = 0;
    for (TopExp_Explorer ex(cad.solids[i], TopAbs_FACE); ex.More(); ex.Next()) {
      const int f = cad.face_index.FindIndex(ex.Current()) - 1;
      area += f >= 0 ? face_area(cad, static_cast<size_t>(f)) : exact_area(ex.Current());
    }
    v = {exact_volume(cad.solids[i]), area};
  }
  return v;
}

// The CAD volume of each solid number. Solids that overlap come out of the
// fuse in pieces, the common one numbered after the first of them
// (number_subshapes); the facets carry the number, so a number's pieces are
// measured together.
std::map<int, double> volume_by_number(const CadModel::Impl& cad) {
  std::map<int, double> volume;
  for (size_t i = 0; i < cad.solids.size(); ++i)
    volume[cad.solid_number[i]] += std::abs(solid_integrals(cad, i)[0]);
  return volume;
}

// Each face's value: the smallest of its solids' (`by_solid`, by solid
// number). front/back: the solids on each face's sides (face_sides).
std::vector<double> smallest_of_solids(const std::vector<int>& front, const std::vector<int>& back,
                                       const std::map<int, double>& by_solid) {
  std::vector<double> value(front.size(), std::numeric_limits<double>::infinity());
  for (size_t f = 0; f < front.size(); ++f)
    for (const int solid : {front[f], back[f]}) {
      const auto it = by_solid.find(solid);
      if (it != by_solid.end()) value[f] = std::min(value[f], it->second);
    }
  return value;
}

// Each face's chord height: the smallest of its solids'. Rounded down to
// `anchor` (0: the finest height) times a power of two, so that the faces
// are meshed in few calls whose chord heights differ enough for BRepMesh to
// keep, at each call, what the finer calls made (cad_tessellate.cpp).
std::vector<double> chord_heights(const std::vector<int>& front, const std::vector<int>& back,
                                  const std::map<int, double>& solid_deflection, double anchor) {
  std::vector<double> height = smallest_of_solids(front, back, solid_deflection);
  if (!(anchor > 0) && !height.empty()) anchor = *std::min_element(height.begin(), height.end());
  for (double& h : height) h = anchor * std::exp2(std::floor(std::log2(h / anchor) + 1e-9));
  return height;
}

// Each face's size, by face index: `size`, or on a part whose solids touch
// nowhere (no face between two), for a face of a solid whose mean thickness
// 2V/A (`thickness`, by solid number) is under size / factor, factor times
// that thickness, unless that is under kThinSizeFloor times the size: a
// foil 0.03 thick and 100 wide, held at a quarter of the size (47 times its
// thickness), was all slivers, and the sliver pass ran past 15 minutes (34
// s at the size; a tester, 2026-11-30). At the size chosen from the part's
// diagonal, a plate 0.2 thick and 50 wide got one layer of tetrahedra with
// edges 14 times its thickness, and 0.011 deg (a disk 0.3 thick: 0.010
// deg; Gmsh's default 2.95 deg); at 4 times the thickness 11.6 and 16.3
// deg (with faces that slide, facet_witnesses.cpp).
//
// Solids that touch keep the size: on gmsh_simple_plane.brep (27 solids,
// its nose pieces 2V/A 0.0006 and its wings thin at size 0.19) the chain of
// tessellations ended elsewhere, 0.70 -> 1.85 % off a wing's volume (at
// least a quarter of the size; at a tenth 1.45 % and 898k tetrahedra with
// 21k under 10 deg, against 489k and 7k).
//
// The facets this adds are bounded, counted on the face tessellation `s`
// as the splits to the sizes would make them (a facet's area over the
// size's equilateral triangle, or its longest edge over the size if more:
// OpenCASCADE's strips on a thin cylinder are split along their length
// only): past kThinFacetGrowth times those at the size, or kThinFacetBudget
// more if that is more, the bounded sizes grow alike until it holds. Counted
// by area alone and allowed 16 times, pythonocc_11752.stp (552 mm wide, 2V/A
// 3.8 mm, size 51.9 mm) got size 15 on its pins (radius 1.6, 1140 long) as
// on its plates, 61,054 facets on each pin, 10.9M in all, and ran 4 minutes
// and 3.4 GB before its refusal (34 s without; 40 s now).
constexpr double kThinFacetGrowth = 1.5;
constexpr double kThinFacetBudget = 50000.0;
constexpr double kThinSizeFloor = 0.25;

std::vector<double> thin_solid_face_sizes(const CadSurface& s, const std::vector<int>& front,
                                          const std::vector<int>& back, const std::map<int, double>& thickness,
                                          double size, double factor) {
  std::vector<double> h = smallest_of_solids(front, back, thickness);
  for (size_t f = 0; f < h.size(); ++f)
    if (front[f] > 0 && back[f] > 0 && front[f] != back[f]) factor = 0;  // solids that touch keep the size
  for (double& x : h) x = factor > 0 && factor * x < size && factor * x >= kThinSizeFloor * size ? factor * x : size;
  auto facets = [&](const std::vector<double>& face_size) {
    double n = 0;
    for (size_t f = 0; f < s.mesh.triangles.size(); ++f) {
      const Triangle& t = s.mesh.triangles[f];
      const double hf = face_size[s.facet_face[f]];
      double longest = 0;
      for (int k = 0; k < 3; ++k)
        longest = std::max(longest, norm(s.mesh.points[t.v[k]] - s.mesh.points[t.v[(k + 1) % 3]]));
      n += std::max({1.0, new_facets(facet_area(s.mesh.points, t), hf), longest / hf});
    }
    return n;
  };
  if (std::all_of(h.begin(), h.end(), [size](double x) { return x == size; })) return h;
  const double uniform = facets(std::vector<double>(h.size(), size));
  double bounded = facets(h);
  const double allowed = std::max(kThinFacetGrowth * uniform, uniform + kThinFacetBudget);
  // The strips' share shrinks with the size, not its square: a few rounds.
  for (int round = 0; round < 8 && bounded > allowed; ++round) {
    const double grow = std::sqrt(bounded / allowed);
    for (double& x : h) x = std::min(size, grow * x);
    bounded = facets(h);
  }
  return h;
}

// Each face's angular deflection in radians: the smallest of its solids'.
std::vector<double> face_angles(const std::vector<int>& front, const std::vector<int>& back,
                                const std::map<int, double>& solid_angle_deg) {
  std::vector<double> angle = smallest_of_solids(front, back, solid_angle_deg);
  for (double& a : angle) a *= M_PI / 180.0;
  return angle;
}

}  // namespace

Mesh CadModel::tessellate(const TessellationOptions& options, TessellationStats* stats_out) const {
  TessellationStats stats;
  stats.size = options.size > 0 ? options.size : default_size();
  stats.size_chosen = !(options.size > 0);
  // Chord height: a tenth of the size, and at most 1/50 of the mean
  // thickness 2V/A of the solids on either side of the face, so that thin
  // parts (wings, blades) keep their volume: gmsh_wing_fuselage.step lost
  // 1.7 % of each solid at size / 10, 0.49 to 0.51 % at thickness / 40 and
  // 0.35 % at thickness / 50. Per solid, not over the assembly: the thin
  // curved plates of gmsh_ellipses.brep lost 3.0 % beside their box, 1.3 %
  // then. Per face, not the thinnest solid's everywhere: the far field
  // around gmsh_simple_plane.brep's 3 mm nose had 923k facets at the nose's
  // chord height. What is still off is measured, and the tessellation made
  // again finer, on the solids that are off only.
  const bool automatic = !(options.deflection > 0);
  std::map<int, double> solid_deflection, solid_angle_deg, solid_thickness;  // by solid number
  for (size_t i = 0; i < impl_->solids.size(); ++i) {
    const auto& [signed_volume, area] = solid_integrals(*impl_, i);
    const double volume = std::abs(signed_volume);
    if (area > 0 && volume > 0) {
      const auto [it, first] = solid_thickness.emplace(impl_->solid_number[i], 2.0 * volume / area);
      if (!first) it->second = std::min(it->second, 2.0 * volume / area);
    }
    const double deflection = options.start_deflection > 0 ? options.start_deflection
                              : area > 0 && volume > 0     ? std::min(stats.size / 10.0, 2.0 * volume / area / 50.0)
                                                           : stats.size / 10.0;
    // The pieces of one overlapping solid (number_subshapes): the finest.
    const auto [it, first] = solid_deflection.emplace(impl_->solid_number[i], deflection);
    if (!first) it->second = std::min(it->second, deflection);
    solid_angle_deg[impl_->solid_number[i]] = options.angle_deg;
  }
  if (options.size > 0 && options.refine) {
    // The refinement to the size is what would run out of memory first;
    // the volume is looked at by the mesher, which knows whether it fills it.
    double area = 0;
    for (size_t f = 0; f < impl_->faces.size(); ++f) area += face_area(*impl_, f);
    check_size_budget(area, 0.0, options.size, /*interior=*/false, "size " + number_text(options.size, "%g"));
  }
  for (const auto& [number, thickness] : solid_thickness)
    stats.thinnest = stats.thinnest > 0 ? std::min(stats.thinnest, thickness) : thickness;
  std::vector<int> front, back;
  face_sides(*impl_, front, back);
  // A chord height over the size bounds nothing the splits to the size do
  // not (a chord no longer than the size sags less), and far over the part
  // OpenCASCADE's mesher leaves gaps between faces: gmsh_part.step (213 mm
  // across) at --deflection 1000 had 7 edges on one facet only, and the
  // mesh was refused as an open surface; at 300, or at its size, none.
  // A chord height far under the part's size makes OpenCASCADE's mesher
  // fill the memory before anything can stop it: 1e-6 on a 100 mm part took
  // 21.9 of 23.5 GB, and a cancel 6 minutes to be heard (1e-5: 1 GB).
  if (options.deflection > 0 && options.deflection < kSmallestRelativeDeflection * impl_->diagonal) {
    std::ostringstream s;
    s << "the chord height (--deflection) " << options.deflection << " is under " << kSmallestRelativeDeflection
      << " of the part's diagonal (" << impl_->diagonal << "): OpenCASCADE's mesher would make more facets than "
      << "memory holds; give at least " << kSmallestRelativeDeflection * impl_->diagonal;
    throw UsageError(s.str());
  }
  std::vector<double> face_deflection(impl_->faces.size(), std::min(options.deflection, stats.size));
  // The heights are rounded against the finest one; starting from one
  // height everywhere (the chain's last link), against that height, so that
  // the faces whose solids the rounds leave alone keep it. Rounded against
  // the nose's new finest height, gmsh_simple_plane.brep's wing roots went
  // finer too, and recovery ran away there. (Rounded against the first
  // round's finest height on every link, caxif_as1-oc-214.stp's second round
  // met EdgeMismatchError.)
  const double anchor = options.start_deflection;
  if (automatic) face_deflection = chord_heights(front, back, solid_deflection, anchor);
  std::vector<double> face_angle = face_angles(front, back, solid_angle_deg);
  // Solids the rounds leave as they are: those on either side of the faces
  // where every earlier recovery ran away (TessellationChain).
  // gmsh_simple_plane.brep's wing roots ran away whenever the wings' chords
  // went finer; its nose, 5 % off, is far from them.
  std::set<int> held;
  for (const int number : options.runaway_faces) {
    const int f = impl_->index_of_face_number(number);
    if (f < 0) continue;
    for (const int solid : {front[f], back[f]})
      if (solid > 0) held.insert(solid);
  }
  stats.held_solids.assign(held.begin(), held.end());
  double seconds_tessellate = 0, seconds_refine = 0, first_facets = 0, previous_worst = 0, best_facets = 0;
  std::vector<char> held_index(impl_->solids.size(), 0);  // `held` by solid index
  for (size_t i = 0; i < impl_->solids.size(); ++i) held_index[i] = held.count(impl_->solid_number[i]) ? 1 : 0;
  std::vector<double> previous_errors;  // the previous round's, by solid index
  Mesh best;  // the previous round's surface
  TessellationStats best_stats;
  try {
    for (int round = 1;; ++round) {
      TessellationStats pass = stats;
      const double deflection = *std::min_element(face_deflection.begin(), face_deflection.end());
      pass.deflection = deflection;
      pass.face_deflection.assign(impl_->faces.size() + 1, 0.0);
      for (size_t f = 0; f < impl_->faces.size(); ++f) {
        const size_t n = static_cast<size_t>(impl_->face_number[f]);
        if (n >= pass.face_deflection.size()) pass.face_deflection.resize(n + 1, 0.0);
        pass.face_deflection[n] = face_deflection[f];
      }
      pass.angle_deg = *std::min_element(face_angle.begin(), face_angle.end()) * 180.0 / M_PI;
      pass.rounds = round;
      auto previous_round = [&]() {
        best_stats.seconds_tessellate = seconds_tessellate;
        best_stats.seconds_refine = seconds_refine;
        if (stats_out) *stats_out = best_stats;
        return std::move(best);
      };
      CadSurface s;
      try {
        s = tessellate_faces(*impl_, face_deflection, face_angle, pass, options.cancel);
      } catch (const EdgeMismatchError&) {
        // A finer round that cannot be welded: the previous one stands.
        if (round == 1) throw;
        return previous_round();
      }
      // Far below the chord height: the move is lost in the tessellation's own error.
      pass.collapsed_edges = collapse_short_edges(s, std::min(0.1 * deflection, 0.01 * pass.size));
      throw_if_cancelled(options.cancel);
      if (options.refine) {
        const std::vector<double> face_size = thin_solid_face_sizes(
            s, front, back, solid_thickness, pass.size, pass.size_chosen ? options.thin_size_factor : 0.0);
        for (const double h : face_size)
          if (h < pass.size) {
            ++pass.thin_faces;
            pass.thin_size = pass.thin_faces == 1 ? h : std::min(pass.thin_size, h);
          }
        refine_to_size(*impl_, s, options, face_size, face_deflection, pass);
      }
      seconds_tessellate += pass.seconds_tessellate;
      seconds_refine += pass.seconds_refine;
      pass.seconds_tessellate = seconds_tessellate;
      pass.seconds_refine = seconds_refine;
      // The chords of a convex face cut into its solid: the thin curved
      // plates of gmsh_ellipses.brep lost 1.3 % at thickness / 50. Both
      // criteria of OpenCASCADE's mesher bound the chords' sag, which the
      // volume error follows: chord height linearly, the angle squared.
      const std::vector<double> errors = volume_errors(s.mesh);
      // The rounds go by the solids they may refine; the report gives all.
      double worst = 0;
      for (size_t i = 0; i < errors.size(); ++i)
        if (!held_index[i]) worst = std::max(worst, errors[i]);
      const double facets = static_cast<double>(s.mesh.triangles.size());
      if (round == 1) first_facets = facets;
      // Facets grow as the chord height shrinks: the shrink is bounded so
      // that the surface ends with at most kMaxFacetGrowth times the first
      // round's facets. An error that does not follow the chords (a broken
      // tessellation: pythonocc_11752.stp) stops the rounds. Each solid that
      // is off shrinks by what it needs: on gmsh_simple_plane.brep the nose
      // pieces (5 % off) need a chord height 6 times smaller than the wings
      // (0.8 % off) do.
      const double fewest = facets / (kMaxFacetGrowth * first_facets);
      std::map<int, double> solid_shrink;  // by solid number, the solids that are off
      for (size_t i = 0; i < errors.size(); ++i)
        if (errors[i] > options.volume_tolerance && !held_index[i])
          solid_shrink[impl_->solid_number[i]] = std::max(0.8 * options.volume_tolerance / errors[i], fewest);
      // The worst solid's (its shrink is the smallest); only asked while it is off.
      double shrink = 1.0;
      for (const auto& [n, solid] : solid_shrink) shrink = std::min(shrink, solid);
      // A smaller chord height need not make more facets: where the size
      // splits bound the sag (a sphere of radius 10 at size 2: 0.67 % at
      // chord 0.13 and 0.84 % at 0.06, with fewer facets), the round is no
      // test of the chords, and the next goes finer still.
      const bool finer = round == 1 || facets > 1.05 * best_facets;
      const bool better =
          round == 1 || (worst < previous_worst && !pushes_a_held_solid_over(previous_errors, errors, held_index,
                                                                              options.volume_tolerance));
      // Converging: a finer round takes 30 % off at least. This stops the
      // rounds where the first round's error was the size's, not the
      // chords' (a sphere of radius 10 and a cylinder fused, at size 1.96:
      // 0.87 -> 0.62 %, and left there, over the tolerance; a third round
      // gives 0.32 %; a FreeCAD tester's part, 2026-11-30). A tenth was
      // tried: the CAD corpus at its sizes kept every mesh, but
      // gmsh_simple_plane.brep at size 0.32 went past the uniform chord
      // height it meshed on (0.00032) to 0.00024, 33 -> 97 s.
      const bool converging = round == 1 || !finer || worst < 0.7 * previous_worst;
      // Only the facets around the solids that are off grow.
      double next_facets = 0;
      for (const Triangle& t : s.mesh.triangles) {
        double grow = 1;
        for (const int solid : {t.front, t.back}) {
          const auto it = solid_shrink.find(solid);
          if (it != solid_shrink.end()) grow = std::max(grow, 1.0 / it->second);
        }
        next_facets += grow;
      }
      const bool affordable = next_facets <= kMaxRoundFacets;
      pass.volume_error = *std::max_element(errors.begin(), errors.end());
      // Finer and no better: the previous round stands.
      if (finer && !better) return previous_round();
      if (!automatic || !(options.volume_tolerance > 0) || worst <= options.volume_tolerance ||
          round == kMaxTessellationRounds || !converging || shrink > 0.8 || !affordable) {
        if (!better) return previous_round();
        if (stats_out) *stats_out = pass;
        return std::move(s.mesh);
      }
      if (better) {
        best = std::move(s.mesh);
        best_stats = pass;
        previous_worst = worst;
        previous_errors = errors;
        best_facets = facets;
      }
      // Finer only where the volume is off: the solids over the tolerance
      // and the faces around them.
      for (const auto& [n, solid] : solid_shrink) {
        solid_deflection[n] *= solid;
        solid_angle_deg[n] *= std::sqrt(solid);
      }
      face_deflection = chord_heights(front, back, solid_deflection, anchor);
      face_angle = face_angles(front, back, solid_angle_deg);
    }
  } catch (const Standard_Failure& e) {
    throw InputError(impl_->name + ": OpenCASCADE failed while tessellating: " + e.GetMessageString());
  }
}

std::vector<double> CadModel::volume_errors(const Mesh& surface) const {
  const std::vector<double> volume = enclosed_volumes(surface);
  const std::map<int, double> cad = volume_by_number(*impl_);
  std::vector<double> error(impl_->solids.size(), 0.0);
  for (size_t i = 0; i < impl_->solids.size(); ++i) {
    const int n = impl_->solid_number[i];
    const double whole = cad.at(n);
    if (whole > 0 && n < static_cast<int>(volume.size())) error[i] = std::abs(volume[n] / whole - 1.0);
  }
  return error;
}

FaceProjector::FaceProjector(const TopoDS_Face& face) {
  const Handle(Geom_Surface) surface = BRep_Tool::Surface(face, location_);
  if (!surface.IsNull()) analyser_ = new ShapeAnalysis_Surface(surface);
}

gp_Pnt FaceProjector::local(const Vec3& p) const {
  gp_Pnt q(p.x, p.y, p.z);
  if (!location_.IsIdentity()) q.Transform(location_.Transformation().Inverted());
  return q;
}

gp_Pnt2d FaceProjector::near_period(gp_Pnt2d uv, const gp_Pnt2d& near) const {
  const Handle(Geom_Surface)& s = analyser_->Surface();
  if (s->IsUPeriodic()) uv.SetX(uv.X() + s->UPeriod() * std::round((near.X() - uv.X()) / s->UPeriod()));
  if (s->IsVPeriodic()) uv.SetY(uv.Y() + s->VPeriod() * std::round((near.Y() - uv.Y()) / s->VPeriod()));
  return uv;
}

gp_Pnt2d FaceProjector::uv(const Vec3& p, double tolerance, const gp_Pnt2d* near) const {
  const gp_Pnt2d uv = analyser_->ValueOfUV(local(p), tolerance);
  return near ? near_period(uv, *near) : uv;
}

gp_Pnt2d FaceProjector::uv_from(const gp_Pnt2d& start, const Vec3& p, double tolerance, double max_gap) const {
  // Gauss-Newton on |S(u, v) - p|^2, a first-derivative evaluation a step.
  // ShapeAnalysis_Surface::NextValueOfUV took 108 us a point on
  // gmsh_ellipses.brep's rational B-splines (the global search 227 us),
  // most of it in its own fallback to the global search.
  const gp_Pnt q = local(p);
  const Handle(Geom_Surface)& surface = analyser_->Surface();
  double u0, u1, v0, v1;
  surface->Bounds(u0, u1, v0, v1);
  const bool u_periodic = surface->IsUPeriodic(), v_periodic = surface->IsVPeriodic();
  double u = start.X(), v = start.Y();
  for (int step = 0; step < 16; ++step) {
    gp_Pnt x;
    gp_Vec su, sv;
    try {
      surface->D1(u, v, x, su, sv);
    } catch (const Standard_Failure&) {
      break;  // no derivative there (OpenCASCADE throws): the global search
    }
    const gp_Vec r(q, x);
    const double a = su.SquareMagnitude(), b = su.Dot(sv), c = sv.SquareMagnitude();
    const double det = a * c - b * b;
    if (!(det > 1e-12 * a * c)) break;  // a pole or a fold: no tangent plane
    const double gu = su.Dot(r), gv = sv.Dot(r);
    const double u_was = u, v_was = v;
    u -= (c * gu - b * gv) / det, v -= (a * gv - b * gu) / det;
    // Pushed past the surface's bounds: the nearest point may lie along the
    // bound, which this step does not find; the global search decides.
    // (A hair past, a vertex on the bound: clamped.)
    const double du_slack = 1e-9 * (u1 - u0), dv_slack = 1e-9 * (v1 - v0);
    if ((!u_periodic && (u < u0 - du_slack || u > u1 + du_slack)) ||
        (!v_periodic && (v < v0 - dv_slack || v > v1 + dv_slack)))
      break;
    if (!u_periodic) u = std::clamp(u, u0, u1);
    if (!v_periodic) v = std::clamp(v, v0, v1);
    if ((su * (u - u_was) + sv * (v - v_was)).Magnitude() > tolerance) continue;
    if (surface->Value(u, v).SquareDistance(q) > max_gap * max_gap) break;
    return near_period(gp_Pnt2d(u, v), start);
  }
  return near_period(analyser_->ValueOfUV(q, tolerance), start);
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
  Vec3 place_node(const std::vector<int>& faces, const Vec3& a, const Vec3& b) const override {
    const Vec3 chord = 0.5 * (a + b);
    std::set<int> distinct(faces.begin(), faces.end());
    try {
      if (distinct.size() == 1) return node_on_face(*distinct.begin(), a, b, chord);
      // On an edge where three faces meet (a cylinder on a box, partly
      // overhanging it: its side, the box's top and their interface), any
      // two with a border edge there will do; the nearest point wins. With
      // two faces only until 2026-11-30: such mid nodes stayed on the chord,
      // 0.0076 inside a circle of radius 4.
      Vec3 best = chord;
      double nearest = -1;
      for (auto a = distinct.begin(); a != distinct.end(); ++a)
        for (auto b = std::next(a); b != distinct.end(); ++b) {
          bool found = false;
          const Vec3 on = on_border(*a, *b, chord, &found);
          const double d = norm(on - chord);
          if (found && (nearest < 0 || d < nearest)) best = on, nearest = d;
        }
      return best;
    } catch (const Standard_Failure&) {
    }
    return chord;
  }

  // Newton's method from near's (u, v): the global search for each of the
  // sliver pass's moves (Extrema_GenExtPS's grid) was most of its time on
  // gmsh_wing_fuselage.step's B-splines.
  std::optional<Vec3> project_onto_face(int number, const Vec3& p, const Vec3& near) const override {
    const int fi = cad_.index_of_face_number(number);
    if (fi < 0) return std::nullopt;
    try {
      const FaceProjector& face = projector(fi);
      if (!face.valid()) return std::nullopt;
      const double tolerance = 1e-9 * cad_.diagonal, reach = norm(p - near);
      const gp_Pnt2d start = vertex_uv(fi, face, near, std::max(reach, tolerance));
      const gp_Pnt2d uv = face.uv_from(start, p, tolerance, std::max(reach, tolerance));
      const Vec3 on = face.point(uv);
      vertex_uv_.emplace(VertexKey{fi, on.x, on.y, on.z}, uv);
      return on;
    } catch (const Standard_Failure&) {
    }
    return std::nullopt;
  }

  std::vector<double> region_volumes() const override {
    std::vector<double> volume;
    for (size_t i = 0; i < cad_.solids.size(); ++i) {
      const size_t n = static_cast<size_t>(cad_.solid_number[i]);
      if (n >= volume.size()) volume.resize(n + 1, 0.0);
      volume[n] += std::abs(solid_integrals(cad_, i)[0]);  // pieces of one solid (below)
    }
    return volume;
  }

 private:
  Vec3 on_face(int number, const Vec3& p) const {
    const int fi = cad_.index_of_face_number(number);
    if (fi < 0) return p;
    const FaceProjector& face = projector(fi);
    return face.valid() ? face.point(face.uv(p, 1e-9 * cad_.diagonal)) : p;
  }

  const FaceProjector& projector(int fi) const {
    auto it = projectors_.find(fi);
    if (it == projectors_.end()) it = projectors_.emplace(fi, FaceProjector(cad_.faces[fi])).first;
    return it->second;
  }

  // A second-order node inside a face: Newton's method from the middle of
  // its edge's ends in (u, v), each end found from the face's vertex before
  // it. The global search of ValueOfUV for every node (Extrema_GenExtPS's
  // grid) took 34 of gmsh_ellipses.brep's 45 s at order 2. Newton's answer
  // farther than half the edge from the chord's middle is no foot of it:
  // the global search decides there.
  Vec3 node_on_face(int number, const Vec3& a, const Vec3& b, const Vec3& chord) const {
    const int fi = cad_.index_of_face_number(number);
    if (fi < 0) return chord;
    const FaceProjector& face = projector(fi);
    if (!face.valid()) return chord;
    const double reach = 0.5 * norm(b - a);
    const gp_Pnt2d ua = vertex_uv(fi, face, a, reach), ub = face.near_period(vertex_uv(fi, face, b, reach), ua);
    const gp_Pnt2d middle(0.5 * (ua.X() + ub.X()), 0.5 * (ua.Y() + ub.Y()));
    return face.point(face.uv_from(middle, chord, 1e-9 * cad_.diagonal, reach));
  }

  // A surface vertex's (u, v) on face fi, kept. From the face's last vertex
  // by Newton's method; an answer farther than `reach` from the vertex (half
  // an edge of it) is no foot of it, and the global search decides.
  gp_Pnt2d vertex_uv(int fi, const FaceProjector& face, const Vec3& p, double reach) const {
    const VertexKey key{fi, p.x, p.y, p.z};
    const auto known = vertex_uv_.find(key);
    if (known != vertex_uv_.end()) return known->second;
    const double tolerance = 1e-9 * cad_.diagonal;
    const auto last = last_uv_.find(fi);
    const gp_Pnt2d uv = last == last_uv_.end() ? face.uv(p, tolerance) : face.uv_from(last->second, p, tolerance, reach);
    last_uv_[fi] = uv;
    vertex_uv_.emplace(key, uv);
    return uv;
  }
  bool is_plane(int number) const {
    const int fi = cad_.index_of_face_number(number);
    if (fi < 0) return false;
    auto it = plane_.find(fi);
    if (it == plane_.end())
      it = plane_.emplace(fi, BRepAdaptor_Surface(cad_.faces[fi]).GetType() == GeomAbs_Plane).first;
    return it->second;
  }

  // `found` (optional): whether a point of the border was found (else p).
  Vec3 on_border(int a, int b, const Vec3& p, bool* found = nullptr) const {
    if (found) *found = false;
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
    if (found) *found = best >= 0;
    return out;
  }

  const CadModel::Impl& cad_;
  std::map<std::pair<int, int>, std::vector<TopoDS_Edge>> border_edges_;
  mutable std::map<int, FaceProjector> projectors_;
  mutable std::map<int, bool> plane_;
  struct VertexKey {
    int face;
    double x, y, z;
    bool operator<(const VertexKey& o) const { return std::tie(face, x, y, z) < std::tie(o.face, o.x, o.y, o.z); }
  };
  mutable std::map<VertexKey, gp_Pnt2d> vertex_uv_;  // second-order nodes' edge ends, slid vertices
  mutable std::map<int, gp_Pnt2d> last_uv_;          // by face index, the last vertex's
};

}  // namespace

std::unique_ptr<SurfaceGeometry> CadModel::geometry() const { return std::make_unique<CadGeometry>(*impl_); }

std::vector<GeometryCheck> CadModel::volume_checks(const Mesh& mesh) const {
  const std::vector<double> volume = region_volumes(mesh);
  std::vector<GeometryCheck> out;
  for (const auto& [n, cad] : volume_by_number(*impl_))
    out.push_back({"Solid" + std::to_string(n), cad, n < static_cast<int>(volume.size()) ? volume[n] : 0.0});
  return out;
}

std::vector<SolidOverlap> CadModel::overlaps() const {
  std::vector<SolidOverlap> out;
  for (size_t s = 0; s < impl_->solids.size() && s < impl_->solid_origins.size(); ++s)
    if (impl_->solid_origins[s].size() > 1)
      out.push_back({impl_->solid_origins[s], std::abs(solid_integrals(*impl_, s)[0])});
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
  // The fuse may cut an input face into pieces that keep its number (the
  // Exhaust's Face15: five, one of 0.011 mm2 where a solid's outline crosses
  // it); the facets carry the number, so the pieces' areas add up. A piece
  // on two input faces counts for each (face_groups), as its facets do in
  // the groups written.
  std::map<int, double> group_area;
  for (const auto& [face, a] : area)
    for (const int g : face_groups_of(mesh, face)) group_area[g] += a;
  area.swap(group_area);
  std::map<int, double> cad_area;
  for (size_t f = 0; f < impl_->faces.size(); ++f)
    for (const int g : face_groups_of(mesh, impl_->face_number[f])) cad_area[g] += face_area(*impl_, f);
  std::vector<GeometryCheck> out;
  for (const auto& [n, a] : cad_area) out.push_back({"Face" + std::to_string(n), a, area.count(n) ? area[n] : 0.0});
  return out;
}

}  // namespace vd::cad
