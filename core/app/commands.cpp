#include "app/args.h"
#include "app/commands.h"

#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <memory>
#include <set>

#include <CGAL/version.h>

#include "app/cad_plugin_loader.h"
#include "app/terminal_progress.h"
#include "app/tuned_allocator.h"
#include "converters/registry.h"
#include "delaunay/oracles.h"
#include "mesh/error.h"
#include "mesh/parallel.h"
#include "mesh/second_order.h"
#include "pipeline/mesher.h"
#include "quality/conformity.h"
#include "quality/tet_quality.h"
#include "volume/region_tetrahedra.h"

namespace vd::app {
namespace {

const char* kMeshHelp =
    "usage: vdmesh mesh INPUT -o OUTPUT [options]\n"
    "  INPUT   CAD part or assembly: .step .stp .iges .igs .brep .brp (solids; touching solids are fused)\n"
    "          or a closed triangulated surface: .off .stl .obj .ply .msh .vtk .vtu .mesh .smesh .poly .node (.gz too)\n"
    "  OUTPUT  .vtu .vtk .msh .inp .mesh .node (volume) or a surface format\n"
    "options:\n"
    "  --size H                target edge length (default: surface input: from its edges, graded;\n"
    "                          CAD input: bounding box diagonal / 25, reported, and on solids that\n"
    "                          touch no other and are thinner than a quarter of it, 4 x their\n"
    "                          mean thickness 2V/A on their faces)\n"
    "  --deflection D          CAD: chord height of the face tessellation\n                          (default: per face, size / 10, at most 2V/A / 50 of the solids\n                          on either side; at most the size)\n"
    "  --angular-deflection DEG  CAD: largest angle between the normals along a facet of a curved face\n"
    "                          (on remeshed cylinders: along the border arcs; default 20; the starting\n"
    "                          value under --volume-tolerance; without it,\n"
    "                          --deflection, --max-passes and --max-added, a recovery that stops at\n"
    "                          its guards is tried again: unsmoothed, then with one chord height\n"
    "                          everywhere (size / 500), then at 30 and 40)\n"
    "  --volume-tolerance PCT  CAD, automatic chord height: tessellate again, with chord height and angle\n"
    "                          made smaller, while a solid's volume is off the CAD volume by more than\n"
    "                          PCT % (default 0.4; at most 4 tessellations; 0: once); split vertices\n"
    "                          stay on the chord where the CAD point would take a solid farther past it\n"
    "  --planar-splits         CAD: split vertices at chord mid-points (the paper) instead of on the CAD geometry\n"
    "  --full-fuse             CAD: fuse the solids in full at once (by default they are glued first, as\n"
    "                          touching only, and fused in full when the glued surface crosses itself)\n"
    "  --no-smoothing          CAD: keep the tessellation's vertices inside faces where they are (by default\n"
    "                          those with a corner under 30 or over 120 deg move, on the CAD face, towards\n"
    "                          their neighbours' middle; a smoothed surface that fails is meshed again unsmoothed)\n"
    "  --no-face-remesh        CAD: keep the refined tessellation of the faces (by default each face's inside\n"
    "                          is meshed anew by Delaunay refinement in a chart of (u, v) that keeps angles,\n"
    "                          exactly on planes, cylinders, cones, spheres and tori, nearly elsewhere (kept\n"
    "                          there only when rounder); corners over 20.7 deg, edges within the size and the\n"
    "                          chord height; the border nodes are kept, with splits where the refinement needs them)\n"
    "  --gradation G           largest growth of the size per unit distance (default 0.3)\n"
    "  --no-interior           no interior vertices: only the surface vertices are tetrahedralized\n"
    "  --surface-grading R     with interior vertices: split surface edges longer than R x the surface's\n"
    "                          graded size (its shortest edges, grown by the gradation), with flips inside\n"
    "                          faces; at least 1, default 2; 0: off. CAD input: off by default; when\n"
    "                          given, done on the CAD faces (size floor: size / 5)\n"
    "  --sliver-angle DEG      tetrahedra under this dihedral angle are slivers, removed or improved\n"
    "                          (default 20; CAD input 10, then 20 when every tetrahedron reached 10;\n"
    "                          at most 70.5)\n"
    "  --keep-slivers          no sliver removal: the Delaunay tetrahedra as they are\n"
    "  --delaunay-surface      the sliver pass keeps every surface facet a face of the Delaunay\n"
    "                          tetrahedralization of the output's vertices (a vertex move that would\n"
    "                          break that is refused); default off with interior vertices (moves\n"
    "                          need only keep every tetrahedron positive, and reach better angles),\n"
    "                          always on without them (--no-interior)\n"
    "  --cautious              interior vertices that take no surface facet, no cap fold splits (what a\n"
    "                          run falls back to when the recovery with interior vertices stops)\n"
    "  --volume METHOD         delaunay (default): the tetrahedra of the Delaunay tetrahedralization;\n"
    "                          advancing-front: the paper's advancing-front Delaunay from the facets\n"
    "                          (the same tetrahedra on vertices in general position, slower)\n"
    "  --order 1|2             element order (default 1); 2: 10-node tetrahedra, and on CAD input the\n"
    "                          mid-edge nodes of the surface on the CAD faces and edges\n"
    "  --oracle dt|lp|sphere   facet Delaunayhood test (default dt, the exact tetrahedralization)\n"
    "  --lp-limit N            largest LP solved by the lp oracle (default: no limit)\n"
    "  --no-flips              only splits: every added vertex lies on an input facet\n"
    "  --flip-angle DEG        largest ridge angle a flip may create (default 20)\n"
    "  --sharp-angle DEG       face ids for untagged input: patches split where normals differ more (default 40)\n"
    "  --seed N                random seed (default 1): same input, options and seed give the same mesh\n"
    "  --threads N             threads for the parallel loops (default: one per core; the mesh is the same)\n"
    "  --shift REL             random shift relative to the local edge length (default 1e-4, 0 = none)\n"
    "  --max-passes N          Delaunayzation guard (default 200)\n"
    "  --max-added N           Delaunayzation guard on added vertices (default 20 x input + 1000)\n"
    "  --report FILE.json      write the report (counts, oracle statistics, times, quality); - for the output\n"
    "  --binary                binary variant of the output format where there is one\n"
    "  --quiet                 no progress and no report table\n";

// "-" is the standard output.
void write_text(const std::string& path, const std::string& text) {
  if (path == "-") {
    std::fputs(text.c_str(), stdout);
    return;
  }
  std::ofstream f(path);
  f << text;
  if (!f) throw UsageError("cannot write " + path);
}

// A file the run is to write must have a folder it can be written in, and
// must not be a folder itself: found after the whole run, and called bad
// input (exit 3), until 2026-11-30. `renamed`: written beside and renamed
// into place (write_result), so a read-only file there is replaced.
void check_can_write(const std::string& path, const std::string& option, bool renamed) {
  namespace fs = std::filesystem;
  if (path == "-") return;
  std::error_code error;
  const fs::path folder = fs::path(path).has_parent_path() ? fs::path(path).parent_path() : fs::path(".");
  const std::string named = option + " " + path + ": ";
  if (fs::is_directory(path, error)) throw UsageError(named + "is a folder");
  if (!fs::is_directory(folder, error)) throw UsageError(named + "the folder " + folder.string() + " does not exist");
  if (::access(folder.c_str(), W_OK) != 0)
    throw UsageError(named + "the folder " + folder.string() + " is not writable");
  if (!renamed && fs::exists(path, error) && ::access(path.c_str(), W_OK) != 0)
    throw UsageError(named + "the file is not writable");
}

// Writes into a staging folder beside the output, then moves what the
// writer made into place, so that a failed run leaves no output that could
// pass for a result. A folder, not OUT.part: TetGen's writer makes a set of
// files named after its path's base (OUT.node.part gave OUT.node.part.node,
// and the rename of OUT.node.part then failed on every -o OUT.node).
// A symlink's target is written, a FIFO or device in place, and a replaced
// file keeps its permissions (io::write_target).
void write_result(const Mesh& mesh, const std::string& path, const io::WriteOptions& options) {
  namespace fs = std::filesystem;
  const io::WriteTarget where = io::write_target(path);
  if (where.in_place) return io::write_mesh(mesh, where.path, options, io::format_for(path).name);
  const fs::path target(where.path);
  // A folder of its own (mkdtemp): two runs writing the same output at once
  // shared OUT.part.d, and one moved the other's half-written files.
  io::remove_stale_parts(target.string());
  std::string staging_name =
      (target.parent_path() / (target.filename().string() + ".part." + std::to_string(::getpid()) + ".XXXXXX")).string();
  if (!::mkdtemp(staging_name.data())) throw FileError(path + ": cannot write: " + std::strerror(errno), path, errno);
  const fs::path staging(staging_name);
  std::error_code ignored, ec;
  auto fail_unless_ok = [&] {
    if (ec) throw FileError(path + ": cannot write: " + ec.message(), path, ec.value());
  };
  try {
    io::write_mesh(mesh, (staging / target.filename()).string(), options, io::format_for(path).name);
    if (where.perms) fs::permissions(staging / target.filename(), *where.perms, ignored);
    std::vector<fs::path> made_files;
    for (const fs::directory_entry& made : fs::directory_iterator(staging)) {
      made_files.push_back(target.parent_path() / made.path().filename());
      fs::rename(made.path(), made_files.back(), ec);
      fail_unless_ok();
    }
    fs::remove(staging, ignored);
    // A set's files this write did not make are an earlier mesh's.
    if (const auto& set_files = io::format_for(path).set_files)
      for (const std::string& member : set_files(target.string()))
        if (std::find(made_files.begin(), made_files.end(), fs::path(member)) == made_files.end())
          fs::remove(member, ignored);
  } catch (...) {
    fs::remove_all(staging, ignored);
    throw;
  }
}

std::string missing_facets_path(const std::string& out) {
  std::filesystem::path p(out);
  return (p.parent_path() / (p.stem().string() + ".missing.off")).string();
}

// Leaves the facets that could not be recovered beside the output, and no
// output itself.
void leave_missing_facets(const MeshResult& partial, const std::string& output, const std::string& report_path) {
  Mesh missing;
  missing.points = partial.mesh.points;
  for (const auto& v : partial.report.missing_facets) missing.triangles.push_back({v});
  const std::string where = missing_facets_path(output);
  io::write_mesh(missing, where, {}, "off");
  if (!report_path.empty()) write_text(report_path, report_json(partial.report));
  std::fprintf(stderr, "vdmesh mesh: the facets still missing are in %s\n", where.c_str());
}

MeshResult mesh_surface_file(const std::string& path, const MeshOptions& opt, MeshResult* partial) {
  Mesh input = io::read_mesh(path);
  input.tets.clear();
  input.tet_mid.clear();
  input.triangle_mid.clear();
  if (input.triangles.empty()) throw InputError(path + ": no surface facets to mesh");
  return mesh_surface(input, opt, partial);
}

MeshResult mesh_cad_file(const std::string& path, const MeshOptions& opt, bool splits_on_geometry,
                         const cad::TessellationOptions& tessellation, bool retry_tessellation,
                         cad::CadModel::Fuse fuse, MeshResult* partial) {
  cad::CadMeshOptions copt;
  copt.fuse = fuse;
  if (!retry_tessellation) copt.retry_angles_deg.clear();
  copt.mesh = opt;
  copt.splits_on_geometry = splits_on_geometry;
  copt.tessellation = tessellation;
  if (opt.progress) opt.progress("read CAD");
  set_thread_count(opt.threads);  // the general fuse's threads too
  return cad_plugin().mesh_file(path, copt, partial);
}

// The CAD tessellation options of `mesh` and `convert`.
cad::TessellationOptions tessellation_options(Args& args) {
  cad::TessellationOptions t;
  t.size = args.number("--size", 0.0);
  t.deflection = args.number("--deflection", 0.0);
  t.angle_deg = args.number("--angular-deflection", t.angle_deg);
  t.volume_tolerance = args.number("--volume-tolerance", 100 * t.volume_tolerance) / 100;
  // `mesh` has read these into its MeshOptions already (mesh_cad takes them
  // from there); `convert` writes the surface `mesh` would start from.
  t.grading = args.number("--surface-grading", cad::kCadSurfaceGrading);
  t.gradation = args.number("--gradation", t.gradation);
  t.smooth = !args.flag("--no-smoothing");
  t.remesh = !args.flag("--no-face-remesh");
  if (!(t.deflection == 0 || t.deflection >= cad::kSmallestDeflection))
    throw UsageError("--deflection must be 0 (chosen per face) or at least 1e-7 (OpenCASCADE's precision)");
  if (!(t.angle_deg > 0 && t.angle_deg <= 90)) throw UsageError("--angular-deflection must be in (0, 90]");
  if (!(t.volume_tolerance >= 0)) throw UsageError("--volume-tolerance must not be negative");
  return t;
}

int element_order(Args& args) {
  const long order = args.integer("--order", 1);
  if (order != 1 && order != 2) throw UsageError("--order must be 1 or 2");
  return static_cast<int>(order);
}

}  // namespace

int mesh_command(const std::vector<std::string>& raw) {
  Args args(raw);
  if (args.flag("--help") || args.flag("-h")) {
    std::fputs(kMeshHelp, stdout);
    return 0;
  }
  // A tessellation or a guard given by hand is kept when recovery stops.
  const bool retry_tessellation = !args.has("--angular-deflection") && !args.has("--deflection") &&
                                  !args.has("--max-passes") && !args.has("--max-added");
  // Asked before the option is consumed below: CAD input has its own default.
  const bool sliver_angle_given = args.has("--sliver-angle");
  const bool surface_grading_given = args.has("--surface-grading");
  // -1 inside: no limit, and the default guard.
  const bool lp_limit_given = args.has("--lp-limit"), max_added_given = args.has("--max-added");
  MeshOptions opt;
  const std::string output = args.value("-o", args.value("--output"));
  opt.oracle = args.value("--oracle", "dt");
  const bool size_given = args.has("--size");
  opt.size.uniform = args.number("--size", 0.0);
  opt.size.gradation = args.number("--gradation", opt.size.gradation);
  opt.interior = !args.flag("--no-interior");
  opt.surface_grading = args.number("--surface-grading", opt.surface_grading);
  opt.slivers.sliver_angle_deg = args.number("--sliver-angle", opt.slivers.sliver_angle_deg);
  opt.remove_slivers = !args.flag("--keep-slivers");
  opt.slivers.delaunay_surface = args.flag("--delaunay-surface");
  opt.cautious = args.flag("--cautious");
  const std::string volume = args.value("--volume", "delaunay");
  if (volume == "advancing-front") opt.volume = VolumeMethod::advancing_front;
  else if (volume != "delaunay") throw UsageError("--volume must be delaunay or advancing-front");
  // Checked as read, before the cast to int (4294967297 became 1).
  const auto guard = [&](const char* name, long fallback) {
    const long v = args.integer(name, fallback);
    if (v > std::numeric_limits<int>::max()) throw UsageError(std::string(name) + " must be at most 2147483647");
    return static_cast<int>(v);
  };
  opt.oracle_options.lp_limit = guard("--lp-limit", -1);
  opt.delaunayzation.flips = !args.flag("--no-flips");
  opt.delaunayzation.flip_angle_deg = args.number("--flip-angle", opt.delaunayzation.flip_angle_deg);
  opt.delaunayzation.max_passes = guard("--max-passes", opt.delaunayzation.max_passes);
  opt.delaunayzation.max_added_vertices = guard("--max-added", -1);
  opt.sharp_angle_deg = args.number("--sharp-angle", opt.sharp_angle_deg);
  opt.seed = static_cast<std::uint64_t>(args.integer("--seed", 1));
  const long threads = args.integer("--threads", 0);
  if (threads < 0 || threads > 1024) throw UsageError("--threads must be in [0, 1024]");
  opt.threads = static_cast<int>(threads);
  opt.order = element_order(args);
  opt.shift = args.number("--shift", opt.shift);
  const std::string report_path = args.value("--report");
  io::WriteOptions wopt;
  wopt.binary = args.flag("--binary");
  const bool quiet = args.flag("--quiet");
  const bool planar_splits = args.flag("--planar-splits");
  const cad::CadModel::Fuse fuse =
      args.flag("--full-fuse") ? cad::CadModel::Fuse::in_full : cad::CadModel::Fuse::glued_first;
  const cad::TessellationOptions tessellation = tessellation_options(args);
  const auto pos = args.positionals();
  if (pos.size() != 1) throw UsageError("expected one INPUT (see vdmesh mesh --help)");
  if (output.empty()) throw UsageError("missing -o OUTPUT");
  if (size_given && !(opt.size.uniform > 0)) throw UsageError("--size must be positive");
  if (opt.size.gradation <= 0) throw UsageError("--gradation must be positive");
  if (!(opt.surface_grading == 0 || opt.surface_grading >= 1)) throw UsageError("--surface-grading must be 0 or at least 1");
  if (opt.shift < 0 || opt.shift > 0.1) throw UsageError("--shift must be in [0, 0.1]");
  if (opt.delaunayzation.flip_angle_deg < 0 || opt.delaunayzation.flip_angle_deg > 180)
    throw UsageError("--flip-angle must be in [0, 180]");
  if (opt.slivers.sliver_angle_deg < 0 || opt.slivers.sliver_angle_deg > kLargestSliverAngleDeg)
    throw UsageError("--sliver-angle must be in [0, 70.5]: no tetrahedron has all its dihedral angles over 70.53 deg");
  if (opt.sharp_angle_deg < 0 || opt.sharp_angle_deg > 180) throw UsageError("--sharp-angle must be in [0, 180]");
  if (lp_limit_given && opt.oracle_options.lp_limit < 1) throw UsageError("--lp-limit must be positive");
  if (opt.delaunayzation.max_passes < 0) throw UsageError("--max-passes must not be negative");
  if (max_added_given && opt.delaunayzation.max_added_vertices < 0) throw UsageError("--max-added must not be negative");
  // Unknown output format: a usage error before any work.
  check_can_write(output, "-o", true);
  if (!report_path.empty()) check_can_write(report_path, "--report", false);

  // On a terminal one line per phase, redrawn with its progress and seconds;
  // elsewhere (a log) the phase names only.
  std::unique_ptr<TerminalProgress> display;
  if (!quiet && isatty(fileno(stderr))) {
    display = std::make_unique<TerminalProgress>();
    opt.progress = [shown = display.get()](const std::string& phase) { shown->phase(phase); };
  } else if (!quiet) {
    opt.progress = [](const std::string& phase) { std::fprintf(stderr, "vdmesh: %s\n", phase.c_str()); };
  }

  const bool cad_input = cad::is_cad_file_name(pos[0]);
  if (cad_input && !sliver_angle_given) {
    opt.slivers.sliver_angle_deg = cad::kCadSliverAngleDeg;
    opt.slivers.raised_angle_deg = cad::kCadRaisedSliverAngleDeg;
  }
  if (cad_input && !surface_grading_given) opt.surface_grading = cad::kCadSurfaceGrading;

  MeshResult partial;
  try {
    MeshResult result = cad_input ? mesh_cad_file(pos[0], opt, !planar_splits, tessellation, retry_tessellation,
                                                  fuse, &partial)
                                  : mesh_surface_file(pos[0], opt, &partial);
    if (opt.progress) opt.progress("write " + output);
    write_result(result.mesh, output, wopt);
    display.reset();  // the last line ends before the report table
    result.report.allocator = allocator_in_use();
    if (!report_path.empty()) write_text(report_path, report_json(result.report));
    // With the report on the standard output, the table would break its JSON.
    if (!quiet && report_path != "-") std::fputs(report_table(result.report).c_str(), stdout);
    return 0;
  } catch (const RecoveryError&) {
    display.reset();
    leave_missing_facets(partial, output, report_path);
    throw;
  }
}

int convert_command(const std::vector<std::string>& raw) {
  Args args(raw);
  io::WriteOptions wopt;
  wopt.binary = args.flag("--binary");
  // convert prints nothing but errors and a warning of inverted tetrahedra;
  // --quiet (taken so that scripts may pass `mesh`'s flags to both) silences
  // the warning.
  const bool quiet = args.flag("--quiet");
  const bool reorient = args.flag("--reorient");
  wopt.msh_version = static_cast<int>(args.integer("--msh-version", 41));
  if (wopt.msh_version != 22 && wopt.msh_version != 41) throw UsageError("--msh-version must be 22 or 41");
  const std::string from = args.value("--from"), to = args.value("--to");
  const cad::TessellationOptions topt = tessellation_options(args);
  const std::string order = args.value("--order");
  const auto pos = args.positionals();
  if (pos.size() != 2)
    throw UsageError(
        "usage: vdmesh convert IN OUT [--binary] [--msh-version 22|41] [--order 1|2] [--reorient] [--quiet] [--size H] [--deflection D] "
        "[--angular-deflection DEG] [--volume-tolerance PCT] [--surface-grading R] [--gradation G] [--no-smoothing] [--no-face-remesh]");
  io::format_for(pos[1], to);
  check_can_write(pos[1], "OUT", false);
  if (from.empty() && cad::is_cad_file_name(pos[0])) {
    // CAD to a surface format: the tagged tessellation the mesher would start from.
    const Mesh surface = cad_plugin().tessellate_file(pos[0], topt);
    io::write_mesh(surface, pos[1], wopt, to);
    return 0;
  }
  Mesh mesh = io::read_mesh(pos[0], from);
  // A mesh of another convention (FreeCAD's FemMesh.write to .vtu inverts
  // every tetrahedron) went through silently, and a deck of negative volumes
  // came out.
  if (reorient) turn_inverted_tetrahedra(mesh);
  if (const long turned = count_turned_tetrahedra(mesh); turned > 0 && !quiet)
    std::fprintf(stderr,
                 "vdmesh convert: warning: %ld of %zu tetrahedra of %s are inverted (their corners turn the other "
                 "way); written as read (--reorient turns them)\n",
                 turned, mesh.tets.size(), pos[0].c_str());
  // Second order from a linear mesh puts the nodes at the edge mid-points:
  // without the CAD model there is no better place.
  if (order == "2") make_second_order(mesh);
  else if (order == "1") make_first_order(mesh);
  else if (!order.empty()) throw UsageError("--order must be 1 or 2");
  io::write_mesh(mesh, pos[1], wopt, to);
  return 0;
}

int version_command() {
  std::printf("vdmesh %s\n", VDMESH_VERSION);
  std::printf("  CGAL %s, GLPK %s\n", CGAL_VERSION_STR, lp_solver_version());
  // The plugin is loaded only to say which OpenCASCADE it was built with, or
  // why CAD input will not work on this installation.
  try {
    std::printf("  CAD input: OpenCASCADE %s\n", cad_plugin().opencascade_version);
  } catch (const std::exception& e) {
    std::printf("  CAD input: unavailable (%s)\n", e.what());
  }
  return 0;
}

int info_command(const std::vector<std::string>& raw) {
  Args args(raw);
  const std::string from = args.value("--from");
  const auto pos = args.positionals();
  if (pos.size() != 1) throw UsageError("usage: vdmesh info MESH");
  // A CAD file is not a mesh: say what reads it rather than list mesh extensions.
  if (from.empty() && cad::is_cad_file_name(pos[0]))
    throw UsageError(pos[0] + " is a CAD file; `vdmesh info` reads meshes: `vdmesh convert " + pos[0] +
                     " OUT.vtu` writes its tessellation, `vdmesh mesh " + pos[0] + " -o OUT.vtu` meshes it");
  const Mesh m = io::read_mesh(pos[0], from);
  std::set<int> regions, faces;
  for (const auto& t : m.tets) regions.insert(t.region);
  for (const auto& t : m.triangles) faces.insert(t.face);
  std::printf("%s\n  points %zu, triangles %zu, tetrahedra %zu%s\n", pos[0].c_str(), m.points.size(),
              m.triangles.size(), m.tets.size(), m.second_order() ? " (second order)" : "");
  std::printf("  regions %zu, faces %zu\n", regions.size(), faces.size());
  // By region number in a map: a file's region 2147483647 overflowed a
  // vector indexed by it ("internal error", exit 1). Tetrahedra the file
  // gives no region (a deck without sets, a VTU without a region array) had
  // no volume line.
  // Second order: the curved tetrahedra's volumes (region_volumes' rule).
  std::map<int, double> volume;
  const bool curved = m.tet_mid.size() == m.tets.size() && !m.tets.empty();
  for (size_t i = 0; i < m.tets.size(); ++i) {
    const Tetrahedron& t = m.tets[i];
    volume[t.region] += curved ? quadratic_tet_volume(tet_nodes(m, i))
                               : tet_volume(m.points[static_cast<size_t>(t.v[0])], m.points[static_cast<size_t>(t.v[1])],
                                            m.points[static_cast<size_t>(t.v[2])], m.points[static_cast<size_t>(t.v[3])]);
  }
  for (const auto& [r, v] : volume)
    if (r >= 0) std::printf("  region %d: volume %.9g\n", r, v);
  if (volume.count(kUnknownRegion)) std::printf("  no region: volume %.9g\n", volume.at(kUnknownRegion));
  if (!m.tets.empty()) {
    const QualitySummary q = summarize_quality(m);
    std::printf("  dihedral angle min %.3f max %.3f deg; radius ratio min %.4f mean %.4f\n", q.min_dihedral_deg,
                q.max_dihedral_deg, q.min_radius_ratio, q.mean_radius_ratio);
    std::printf("  inverted %ld; under 5 deg %ld; under 10 deg %ld\n", q.inverted, q.below_5_deg, q.below_10_deg);
    std::printf("  dihedral histogram (10 deg bins):");
    for (long c : q.dihedral_histogram) std::printf(" %ld", c);
    std::printf("\n");
    std::printf("  radius ratio histogram (0.1 bins):");
    for (long c : q.radius_ratio_histogram) std::printf(" %ld", c);
    std::printf("\n");
  }
  return 0;
}

}  // namespace vd::app
