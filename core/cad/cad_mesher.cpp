#include "cad/cad_mesher.h"

#include <chrono>
#include <cstdio>
#include <exception>
#include <map>
#include <sstream>
#include <string>

#include "cad/tessellation_chain.h"
#include "mesh/error.h"
#include "mesh/number_text.h"

namespace vd::cad {

namespace {

std::string format_number(double x) { return number_text(x, "%g"); }

// The crossing facets of a tessellation, said by the CAD faces they belong
// to (the tags a user can find in the part) and where: facet indices alone
// mean nothing outside vdmesh.
std::string crossing_faces(const Mesh& surface, const SelfIntersectionError& error) {
  std::map<std::pair<int, int>, int> first_pair;  // face pair -> first facet pair
  const auto& pairs = error.facet_pairs();
  for (size_t i = 0; i < pairs.size(); ++i) {
    int a = surface.triangles[pairs[i].first].face, b = surface.triangles[pairs[i].second].face;
    first_pair.emplace(std::minmax(a, b), static_cast<int>(i));
  }
  std::ostringstream s;
  s << "the tessellation of the CAD faces crosses itself:";
  const char* separator = " ";
  for (const auto& [faces, i] : first_pair) {
    const Triangle& t = surface.triangles[pairs[i].first];
    const Vec3 c = (1.0 / 3.0) * (surface.points[t.v[0]] + surface.points[t.v[1]] + surface.points[t.v[2]]);
    s << separator << "Face" << faces.first << (faces.first == faces.second ? " with itself" : " with Face")
      << (faces.first == faces.second ? "" : std::to_string(faces.second)) << " near (" << format_number(c.x) << ", "
      << format_number(c.y) << ", " << format_number(c.z) << ")";
    separator = ", ";
  }
  s << " (" << error.what() << ")";
  return s.str();
}

MeshResult mesh_tessellation(const CadModel& model, const CadMeshOptions& options, const TessellationOptions& topt,
                             int retries, int runaways, bool has_fallback, MeshResult* partial) {
  TessellationStats stats;
  const Mesh surface = model.tessellate(topt, &stats);

  MeshOptions mopt = options.mesh;
  mopt.tessellated = true;
  mopt.size.uniform = stats.size;
  // The tessellation was refined and graded on the CAD geometry
  // (cad_refine.cpp); the graded splits of faceted input would put points
  // on the chords.
  mopt.surface_grading = 0;
  if (has_fallback) mopt.delaunayzation.patience_passes = kPatienceWithAFallback;
  // A recovery that runs away on CAD input never came back on the corpus:
  // one with no patience (the uniform chord heights, the last link) is
  // stopped then too, so the halved chords follow at once, and a chain that
  // fails ends in seconds (simple_plane at 0.35 ran 77 passes and 528k
  // vertices on its last link before exit 4, 198 s in all).
  mopt.delaunayzation.stop_running_away = true;
  const auto geometry = model.geometry();
  if (options.splits_on_geometry) {
    mopt.delaunayzation.geometry = geometry.get();
    mopt.delaunayzation.max_flip_offset = stats.deflection;
    mopt.delaunayzation.face_flip_offset = stats.face_deflection;
    mopt.delaunayzation.volume_limit = topt.volume_tolerance;
  }

  CadInputReport cad;
  cad.used = true;
  cad.units = model.units();
  cad.solids = model.solid_count();
  cad.faces = model.face_count();
  cad.interface_faces = model.interface_face_count();
  cad.fuse = model.fuse_kind();
  cad.overlaps = model.overlaps();  // in the partial report of exit 4 too
  cad.size = stats.size;
  cad.size_chosen = stats.size_chosen;
  cad.thin_faces = stats.thin_faces;
  cad.thin_size = stats.thin_size;
  cad.thinnest = stats.thinnest;
  cad.deflection = stats.deflection;
  cad.angle_deg = stats.angle_deg;
  cad.tessellation_rounds = stats.rounds;
  cad.held_solids = stats.held_solids;
  cad.tessellation_volume_error = stats.volume_error;
  cad.occ_triangles = stats.occ_triangles;
  cad.refine_splits = stats.refine_splits;
  cad.refine_flips = stats.refine_flips;
  cad.border_splits = stats.border_splits;
  cad.border_caps_snapped = stats.border_caps_snapped;
  cad.needle_edges_collapsed = stats.needle_edges_collapsed;
  cad.smoothing_moves = stats.smoothing_moves;
  cad.remeshed_faces = stats.remeshed_faces;
  cad.smoothing_dropped = !topt.smooth && options.tessellation.smooth;
  cad.remeshing_dropped = !topt.remesh && options.tessellation.remesh;
  cad.collapsed_edges = stats.collapsed_edges;
  cad.flat_vertices_removed = stats.flat_vertices_removed;
  cad.recovery_retries = retries;
  cad.recovery_runaways = runaways;
  cad.surface_facets = static_cast<int>(surface.triangles.size());
  const std::vector<std::pair<std::string, double>> cad_seconds = {
      {"read CAD", model.seconds_read},
      {"fuse solids", model.seconds_fuse},
      {"tessellate", stats.seconds_tessellate},
      {"refine surface", stats.seconds_refine}};

  MeshResult result;
  const auto keep_partial = [&] {
    if (partial) {
      partial->report.cad = cad;
      partial->report.seconds.insert(partial->report.seconds.begin(), cad_seconds.begin(), cad_seconds.end());
    }
  };
  try {
    result = mesh_surface(surface, mopt, partial);
  } catch (const SelfIntersectionError& e) {
    keep_partial();
    throw SelfIntersectionError(crossing_faces(surface, e), e.facet_pairs());
  } catch (...) {
    keep_partial();
    throw;
  }
  cad.volumes = model.volume_checks(result.mesh);
  cad.areas = model.area_checks(result.mesh);
  result.report.cad = cad;
  result.report.seconds.insert(result.report.seconds.begin(), cad_seconds.begin(), cad_seconds.end());
  return result;
}

// Thrown out of the chain when a glued model's surface is refused: the
// refusal may be the gluing's (solids that cross, left unsplit).
struct GlueRefused {};

// The chain of tessellations on one model (tessellation_chain.h).
MeshResult mesh_chain(const CadModel& model, const CadMeshOptions& options, MeshResult* partial) {
  TessellationOptions topt = options.tessellation;
  topt.size = options.mesh.size.uniform;
  topt.cancel = options.mesh.cancel;
  // The graded refinement of faceted input, done here on the CAD geometry.
  const bool grade = options.mesh.interior && options.mesh.delaunayzation.flips;
  topt.grading = grade ? options.mesh.surface_grading : 0;
  topt.gradation = options.mesh.size.gradation;
  // The last retry, one chord height everywhere: on automatic chord heights
  // with retries only.
  const double uniform_deflection =
      options.uniform_chord_divisor > 0
          ? (topt.size > 0 ? topt.size : model.default_size()) / options.uniform_chord_divisor
          : 0;
  TessellationChain chain(topt, options.retry_angles_deg, uniform_deflection);
  double given_up = 0;  // seconds spent on tessellations whose recovery stopped
  std::string last_recovery_failure;  // reported when the uniform chords fail before recovery
  int runaways = 0;                   // of the recoveries given up, those that ran away
  for (;;) {
    const TessellationOptions& t = chain.options();
    if (options.mesh.progress)
      options.mesh.progress(chain.attempt() == 0
                                ? "tessellate CAD faces"
                                : "tessellate CAD faces again at " + format_number(t.angle_deg) + " deg" +
                                      (chain.on_uniform_chords()
                                           ? ", chord height " + format_number(t.start_deflection) + " everywhere"
                                           : "") +
                                      (t.smooth || t.remesh ? "" : ", unsmoothed, not remeshed"));
    const auto start = std::chrono::steady_clock::now();
    const auto next = [&](bool recovery_stopped, const std::vector<int>& runaway_faces = {}, bool ran_away = false) {
      if (!chain.next(recovery_stopped, runaway_faces, ran_away)) return false;
      given_up += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      return true;
    };
    try {
      MeshResult result = mesh_tessellation(model, options, t, chain.attempt(), runaways, chain.has_fallback(), partial);
      if (chain.attempt() > 0)
        result.report.seconds.insert(result.report.seconds.begin(), {"tessellations recovery gave up on", given_up});
      return result;
    } catch (const RecoveryError& e) {
      last_recovery_failure = e.what();
      // Said before the next tessellation's line: a run that goes on for
      // minutes shows why (the counts and faces are the error's).
      if (options.mesh.progress) options.mesh.progress(std::string("recovery stopped: ") + e.what());
      runaways += e.ran_away();
      if (!next(true, e.faces(), e.ran_away())) throw;
    } catch (const SelfIntersectionError& e) {  // the surface is checked before recovery
      if (model.glued()) throw GlueRefused{};
      if (next(false)) continue;
      // The uniform chords or a later angle crossing themselves says
      // nothing of the file: the recovery failure that led to them stands.
      if (chain.uniform_tried() && !last_recovery_failure.empty()) throw RecoveryError(last_recovery_failure);
      // Every tessellation tried crosses itself: say whether OpenCASCADE
      // finds the file's geometry faulty (pythonocc_11752.stp: crossing
      // edges and curves off their faces, on the faces that cross).
      if (options.mesh.progress) options.mesh.progress("check the CAD shape");
      const std::string faults = model.geometry_faults();
      throw InputError(std::string(e.what()) + "; " +
                       (faults.empty() ? "OpenCASCADE's check of the shape finds it valid" : faults));
    } catch (const InputError&) {
      if (model.glued()) throw GlueRefused{};
      if (next(false)) continue;
      if (chain.uniform_tried() && !last_recovery_failure.empty()) throw RecoveryError(last_recovery_failure);
      throw;
    }
  }
}

// When every link of the chain stopped, the chain once more with the edges
// from corners split on concentric shells (DelaunayzationOptions::
// shell_splits): gmsh_simple_plane.brep at size 0.4067 stalled on each
// uniform chord height (46 facets with edges of 3e-7 to 5e-7, the guard's
// shortest edge, around the CAD vertex where its wing root's skins meet the
// fuselage at small angles: the mid-point splits of the edges around it kept
// taking each other's facets out) and ran away on the other angles (exit 4
// after 46 s); with shells its first uniform height meshes. Only then: on the
// corpus the shells lowered as many smallest angles as they raised, and at
// sizes 0.32 to 0.45 of simple_plane, where the plain chain meshes on finer
// uniform heights, meshing on the first height with shells left up to 9.7 %
// of a solid's volume off (every solid within 0.5 % on the finer ones).
//
// And when that stopped too, the first tessellation once more with the split
// vertices on the chords (--planar-splits), the paper's way. A boss tangent
// to a wall (a solid that touches itself along a line, a FreeCAD tester's
// part, 2026-11-30) ran away on every link, its splits put on the cylinder
// beside the line where it touches the plane, and meshed on the chords
// (31,176 tetrahedra, 1.85 deg, 0.04 % off its volume). Last: the chords
// cost the curved faces their accuracy, and only the first tessellation is
// tried (and it unsmoothed, as the chain does).
MeshResult mesh_chain_or_shells(const CadModel& model, const CadMeshOptions& options, MeshResult* partial) {
  if (options.mesh.delaunayzation.shell_splits) return mesh_chain(model, options, partial);
  const auto start = std::chrono::steady_clock::now();
  const auto since_start = [&] {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  };
  try {
    return mesh_chain(model, options, partial);
  } catch (const RecoveryError&) {
    if (options.mesh.progress)
      options.mesh.progress("every tessellation's recovery stopped; all again with shell splits from corners");
  }
  const double stopped = since_start();
  CadMeshOptions shells = options;
  shells.mesh.delaunayzation.shell_splits = true;
  try {
    MeshResult result = mesh_chain(model, shells, partial);
    result.report.seconds.insert(result.report.seconds.begin(), {"recoveries stopped (mid-point splits)", stopped});
    return result;
  } catch (const RecoveryError&) {
    if (!options.splits_on_geometry) throw;
    const std::exception_ptr shells_failure = std::current_exception();
    if (options.mesh.progress)
      options.mesh.progress("every recovery stopped; the first tessellation once more with split vertices on the chords");
    const double stopped_all = since_start();
    CadMeshOptions planar = options;
    planar.splits_on_geometry = false;
    planar.retry_angles_deg.clear();  // the first tessellation (and it unsmoothed) alone
    MeshResult scratch;  // a failure here leaves the chain's partial result and error
    MeshResult result;
    try {
      result = mesh_chain(model, planar, partial ? &scratch : nullptr);
    } catch (const CancelledError&) {
      throw;
    } catch (...) {  // whatever stopped it (GlueRefused too), the chains' failure is the one to say
      std::rethrow_exception(shells_failure);
    }
    result.report.cad.planar_splits_fallback = true;
    result.report.seconds.insert(result.report.seconds.begin(),
                                 {"recoveries stopped (on the CAD geometry)", stopped_all});
    return result;
  }
}

}  // namespace

MeshResult mesh_cad(const CadModel& model, const CadMeshOptions& options, MeshResult* partial) {
  if (!model.glued()) return mesh_chain_or_shells(model, options, partial);
  const auto start = std::chrono::steady_clock::now();
  try {
    return mesh_chain_or_shells(model, options, partial);
  } catch (const GlueRefused&) {
    // Any refused surface of a glued model: the whole chain again on the
    // full fuse, so that a refusal that is not the gluing's ends as it would
    // have without it (a file that meshes after one costs the fuse again).
    if (options.mesh.progress) options.mesh.progress("fuse the solids in full (the glued surface was refused)");
    const double refused = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    const CadModel full = model.fused_in_full(options.mesh.cancel);
    MeshResult result = mesh_chain_or_shells(full, options, partial);
    for (auto& [phase, seconds] : result.report.seconds)
      if (phase == "fuse solids") seconds += model.seconds_fuse;
    result.report.seconds.insert(result.report.seconds.begin(), {"glued surface refused", refused});
    return result;
  }
}

}  // namespace vd::cad
