// vdmesh compare: vdmesh and TetGen side by side on the same input (issue 6).
// Both meshers run in their own process (vdmesh: this program's hidden
// `compare --worker`), so a crash or a timeout of either is a reported result;
// both meshes are read back from files and go through the same checks
// (core/compare/mesh_checks.h).
#include <stdlib.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>

#include "app/args.h"
#include "app/commands.h"
#include "app/cad_plugin_loader.h"
#include "cad/cad_mesher.h"
#include "cad/tessellation_chain.h"
#include "compare/child_process.h"
#include "compare/compare_report.h"
#include "compare/mesh_checks.h"
#include "compare/svg_histogram.h"
#include "compare/tetgen_runner.h"
#include "converters/registry.h"
#include "mesh/error.h"
#include "mesh/number_text.h"
#include "pipeline/mesher.h"
#include "surface/face_patches.h"

namespace vd::app {
namespace {

using namespace vd::compare;

const char* kCompareHelp =
    "usage: vdmesh compare INPUT [options]\n"
    "  Meshes INPUT with vdmesh and with TetGen, each in its own process, twice:\n"
    "    boundary  vdmesh --no-interior   against  tetgen -pYA   (the input surface kept)\n"
    "    quality   vdmesh [--size H]      against  tetgen -pq1.414aV A, V chosen for a similar count\n"
    "  and checks both meshes the same way: validity, boundary conformity with the input, face and region\n"
    "  tags, region volumes against the input surface, quality. Prints a side-by-side table.\n"
    "  CAD input: both get the tessellation at vdmesh's default size; when vdmesh's recovery stops on it,\n"
    "  the next one `vdmesh mesh` would try (unsmoothed, then 30 and 40 deg), and the table says which.\n"
    "options:\n"
    "  --size H            vdmesh's edge length in the quality run (default: vdmesh's own size field)\n"
    "  --json FILE.json    everything measured, per run and mesher\n"
    "  --svg FILE.svg      dihedral-angle histograms side by side\n"
    "  --keep-dir DIR      keep the meshers' input, output (.vtu copies too) and logs in DIR\n"
    "  --runs LIST         boundary,quality (default both)\n"
    "  --timeout S         time limit of each mesher run in seconds (default 600)\n"
    "  --tetgen PROGRAM    the TetGen program (default tetgen, from PATH)\n"
    "  --seed N            vdmesh's seed (default 1)\n"
    "  --sharp-angle DEG   face ids for input without them (default 40), given to both meshers\n"
    "  --quiet             no progress lines\n"
    "exit codes: 0 vdmesh meshed every run and its meshes pass the checks (TetGen's result never changes\n"
    "  the exit code); 3 INPUT unreadable, or vdmesh refused it; 4 vdmesh could not recover every facet;\n"
    "  5 a vdmesh mesh failed a check; 1 vdmesh crashed or timed out; 2 usage. The table and the JSON are\n"
    "  written whenever INPUT could be read.\n";

std::string read_text(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>());
}

void write_text(const std::string& path, const std::string& text) {
  std::ofstream f(path, std::ios::binary);
  f << text;
  if (!f) throw UsageError("cannot write " + path);
}

// The input exactly as both meshers get it. Input without face ids gets them
// here (smooth patches, as `vdmesh mesh` would), so that TetGen's facet
// markers and vdmesh's face ids are the same. Returns the patch count in
// `patches` (0 when the input had face ids).
// CAD input is tessellated at vdmesh's default CAD size with `tessellation`
// (the same in every process, so the parent and both workers see one
// surface), and both meshers get that surface.
Mesh load_compare_input(const std::string& path, double sharp_angle_deg, const cad::TessellationOptions& tessellation,
                        int* patches = nullptr) {
  Mesh m = cad::is_cad_file_name(path) ? app::cad_plugin().tessellate_file(path, tessellation) : io::read_mesh(path);
  m.tets.clear();
  m.tet_mid.clear();
  m.triangle_mid.clear();
  if (m.triangles.empty()) throw InputError(path + ": no surface facets to mesh");
  const int p = m.has_face_tags() ? 0 : assign_face_patches(m, sharp_angle_deg);
  if (patches) *patches = p;
  return m;
}

// The child side: mesh INPUT with vdmesh and write BASE.node/.ele/.face and
// BASE.report.json. Exit codes as `vdmesh mesh`.
int compare_worker(const std::vector<std::string>& raw) {
  Args args(raw);
  MeshOptions opt;
  opt.interior = !args.flag("--no-interior");
  opt.size.uniform = args.number("--size", 0.0);
  opt.seed = static_cast<std::uint64_t>(args.number("--seed", 1));
  const double sharp = args.number("--sharp-angle", kDefaultSharpAngleDeg);
  if (sharp < 0 || sharp > 180) throw UsageError("--sharp-angle must be in [0, 180]");
  opt.sharp_angle_deg = sharp;
  cad::TessellationOptions tessellation;
  tessellation.angle_deg = args.number("--angular-deflection", tessellation.angle_deg);
  tessellation.smooth = !args.flag("--no-smoothing");
  tessellation.remesh = !args.flag("--no-face-remesh");
  // Another tessellation to fall back on: a recovery that runs away stops
  // early, as in `vdmesh mesh`.
  if (args.flag("--has-fallback")) opt.delaunayzation.patience_passes = cad::kPatienceWithAFallback;
  const auto pos = args.positionals();
  if (pos.size() != 2) throw UsageError("compare --worker INPUT BASE [options]");
  const std::string base = pos[1];
  int patches = 0;
  const Mesh input = load_compare_input(pos[0], sharp, tessellation, &patches);
  opt.faces_are_patches = patches > 0;
  opt.tessellated = cad::is_cad_file_name(pos[0]);
  MeshResult partial;
  try {
    const MeshResult result = mesh_surface(input, opt, &partial);
    io::write_mesh(result.mesh, base + ".node", {}, "tetgen");
    write_text(base + ".report.json", report_json(result.report));
    return 0;
  } catch (const RecoveryError&) {
    write_text(base + ".report.json", report_json(partial.report));
    throw;
  }
}

std::string format_g(double x) { return number_text(x); }

struct Settings {
  std::string input;
  std::string dir;
  bool keep = false;
  double timeout = 600;
  std::string tetgen = "tetgen";
  double seed = 1;
  double sharp = kDefaultSharpAngleDeg;
  bool quiet = false;
  // CAD input: the worker's options for the tessellation both meshers get
  // (a link of the chain of `vdmesh mesh`).
  std::vector<std::string> tessellation_arguments;
};

std::string tessellation_text(const cad::TessellationOptions& t) {
  return "angular deflection " + format_g(t.angle_deg) + " deg" +
         (t.smooth || t.remesh ? "" : ", unsmoothed, not remeshed");
}

std::vector<std::string> tessellation_arguments(const cad::TessellationChain& chain) {
  const cad::TessellationOptions& t = chain.options();
  std::vector<std::string> out = {"--angular-deflection", format_g(t.angle_deg)};
  if (!t.smooth) out.push_back("--no-smoothing");
  if (!t.remesh) out.push_back("--no-face-remesh");
  if (chain.has_fallback()) out.push_back("--has-fallback");
  return out;
}

void progress(const Settings& s, const std::string& what) {
  throw_if_stopped();
  if (!s.quiet) std::fprintf(stderr, "vdmesh compare: %s\n", what.c_str());
}

void check_run(CheckedRun& r, const InputSurface& surface, const Settings& s, const std::string& name) {
  throw_if_stopped();
  if (!r.run.meshed) return;
  r.checks = check_mesh(surface, r.run.mesh);
  r.checked = true;
  if (s.keep) {
    r.mesh_file = (std::filesystem::path(s.dir) / (name + ".vtu")).string();
    io::write_mesh(r.run.mesh, r.mesh_file, {}, "vtu");
  }
  // The meshes can be large; the checks keep what the report needs.
  r.run.mesh = Mesh();
}

CheckedRun run_vdmesh(const Settings& s, const std::string& name, const std::vector<std::string>& options) {
  CheckedRun r;
  MesherRun& run = r.run;
  run.mesher = "vdmesh";
  run.label = "vdmesh";
  for (const auto& o : options) run.label += " " + o;
  const std::string base = (std::filesystem::path(s.dir) / name).string();
  run.log_path = base + ".log";
  for (const char* ext : {".node", ".ele", ".face", ".report.json"}) std::remove((base + ext).c_str());
  std::vector<std::string> argv = {self_executable(), "compare", "--worker", s.input, base, "--seed",
                                   std::to_string(static_cast<long>(s.seed)), "--sharp-angle", std::to_string(s.sharp)};
  argv.insert(argv.end(), options.begin(), options.end());
  argv.insert(argv.end(), s.tessellation_arguments.begin(), s.tessellation_arguments.end());
  for (size_t i = 0; i < argv.size(); ++i) run.command += (i ? " " : "") + argv[i];
  run.process = run_child(argv, run.log_path, s.timeout);
  r.report_json = read_text(base + ".report.json");
  if (!run.process.ok()) {
    run.failure = failure_text(run.process, run.log_path);
    return r;
  }
  try {
    run.mesh = io::read_mesh(base + ".node", "tetgen");
    run.meshed = !run.mesh.tets.empty();
    if (!run.meshed) run.failure = "no tetrahedra in the output";
  } catch (const std::exception& e) {
    run.failure = std::string("output not readable: ") + e.what();
  }
  return r;
}

double total_volume(const MeshChecks& c) {
  double v = 0;
  for (const auto& r : c.regions) v += r.volume;
  return v;
}

// Exit code for vdmesh's side of one run (0: fine).
int vdmesh_exit(const CheckedRun& r) {
  if (!r.run.meshed) {
    const int code = r.run.process.exit_code;
    if (r.run.process.started && !r.run.process.timed_out && r.run.process.signal == 0 && (code == 3 || code == 4))
      return code;
    return 1;
  }
  return r.passed() ? 0 : 5;
}

}  // namespace

int compare_command(const std::vector<std::string>& raw) {
  if (!raw.empty() && raw[0] == "--worker") return compare_worker({raw.begin() + 1, raw.end()});
  Args args(raw);
  if (args.flag("--help") || args.flag("-h")) {
    std::fputs(kCompareHelp, stdout);
    return 0;
  }
  Settings s;
  const bool size_given = args.has("--size");
  const double size = args.number("--size", 0.0);
  const std::string json_path = args.value("--json"), svg_path = args.value("--svg");
  const std::string keep_dir = args.value("--keep-dir");
  const std::string runs = args.value("--runs", "boundary,quality");
  s.timeout = args.number("--timeout", s.timeout);
  s.tetgen = args.value("--tetgen", s.tetgen);
  s.seed = args.number("--seed", 1);
  s.sharp = args.number("--sharp-angle", s.sharp);
  s.quiet = args.flag("--quiet");
  const auto pos = args.positionals();
  if (pos.size() != 1) throw UsageError("expected one INPUT (see vdmesh compare --help)");
  if (size_given && !(size > 0)) throw UsageError("--size must be positive");
  if (s.timeout <= 0) throw UsageError("--timeout must be positive");
  if (s.sharp < 0 || s.sharp > 180) throw UsageError("--sharp-angle must be in [0, 180]");
  if (s.seed < 0 || s.seed != std::floor(s.seed)) throw UsageError("--seed must be a non-negative integer");
  const bool do_boundary = runs.find("boundary") != std::string::npos;
  const bool do_quality = runs.find("quality") != std::string::npos;
  if (!do_boundary && !do_quality) throw UsageError("--runs takes boundary, quality or both");
  s.input = std::filesystem::absolute(pos[0]).string();

  stop_children_on_signals();
  // Unreadable input: nothing to compare (exit 3 through main).
  Comparison cmp;
  int patches = 0;
  const bool cad_input = cad::is_cad_file_name(s.input);
  // CAD input: the tessellations of `vdmesh mesh`, in turn, while vdmesh's
  // recovery stops on one (or its surface is refused): both meshers are
  // compared on the surface vdmesh meshes, as `vdmesh mesh` would find it.
  // Not the link of that chain with one chord height everywhere: its
  // height comes from the CAD model, which this process does not read.
  cad::TessellationChain chain(cad::TessellationOptions{},
                               cad_input ? cad::CadMeshOptions().retry_angles_deg : std::vector<double>{}, 0);
  Mesh input = load_compare_input(s.input, s.sharp, chain.options(), &patches);
  cmp.input = pos[0];
  cmp.size = size;
  cmp.tetgen_program = s.tetgen;
  cmp.timeout_seconds = s.timeout;

  if (!keep_dir.empty()) {
    std::filesystem::create_directories(keep_dir);
    s.dir = std::filesystem::absolute(keep_dir).string();
    s.keep = true;
  } else {
    std::string tmpl = (std::filesystem::temp_directory_path() / "vdmesh-compare-XXXXXX").string();
    if (!mkdtemp(tmpl.data())) throw std::runtime_error("cannot create a temporary folder in " + tmpl);
    s.dir = tmpl;
  }
  cmp.work_dir = s.dir;
  cmp.kept = s.keep;
  // The temporary folder goes whatever happens below.
  struct Cleanup {
    std::string dir;
    ~Cleanup() {
      std::error_code ignored;
      if (!dir.empty()) std::filesystem::remove_all(dir, ignored);
    }
  } cleanup{s.keep ? std::string() : s.dir};

  CheckedRun boundary_vdmesh, quality_vdmesh;
  std::vector<std::string> quality_options;
  if (size > 0) quality_options = {"--size", format_g(size)};
  for (;;) {
    if (cad_input) s.tessellation_arguments = tessellation_arguments(chain);
    if (chain.attempt() > 0) input = load_compare_input(s.input, s.sharp, chain.options(), &patches);
    // False: this run stands. True: the next tessellation is to be tried.
    const auto try_next = [&](const CheckedRun& r, const std::string& run) {
      const int code = r.run.meshed ? 0 : vdmesh_exit(r);
      if (!cad_input || (code != 3 && code != 4)) return false;
      cad::TessellationChain after = chain;
      if (!after.next(code == 4)) return false;
      cmp.tessellations_given_up.push_back(tessellation_text(chain.options()) + ": " + run + " run, vdmesh exit " +
                                           std::to_string(code));
      chain = after;
      progress(s, "CAD tessellation again, " + tessellation_text(chain.options()));
      return true;
    };
    if (do_boundary) {
      progress(s, "boundary run, vdmesh --no-interior");
      boundary_vdmesh = run_vdmesh(s, "boundary-vdmesh", {"--no-interior"});
      if (try_next(boundary_vdmesh, "boundary")) continue;
    }
    if (do_quality) {
      progress(s, "quality run, vdmesh" + (size > 0 ? " --size " + format_g(size) : std::string()));
      quality_vdmesh = run_vdmesh(s, "quality-vdmesh", quality_options);
      if (try_next(quality_vdmesh, "quality")) continue;
    }
    break;
  }
  if (cad_input) cmp.tessellation = tessellation_text(chain.options());
  cmp.input_vertices = static_cast<long>(input.points.size());
  cmp.input_facets = static_cast<long>(input.triangles.size());
  cmp.face_patches = patches;

  const InputSurface surface(input);
  // Without region tags, the input's own region points (a TetGen PLC's hole
  // and region lists, which vdmesh applies too), so that both mesh the
  // same regions.
  const std::vector<RegionPoint> regions = surface.region_tags() ? region_points(surface) : input.region_points;
  cmp.region_tags = surface.region_tags();
  cmp.region_points = static_cast<int>(regions.size());
  const std::string dir = s.dir;
  auto at = [&](const std::string& name) { return (std::filesystem::path(dir) / name).string(); };

  if (do_boundary) {
    RunPair r;
    r.name = "boundary";
    r.title = "boundary-preserving";
    r.vdmesh = std::move(boundary_vdmesh);
    check_run(r.vdmesh, surface, s, "boundary-vdmesh");
    progress(s, "boundary run, tetgen -pYA");
    r.tetgen.run = run_tetgen(input, regions, "pYA", at("boundary-tetgen"), s.tetgen, s.timeout);
    r.tetgen_attempts.emplace_back("-pYA", r.tetgen.run.meshed ? static_cast<long>(r.tetgen.run.mesh.tets.size()) : -1);
    check_run(r.tetgen, surface, s, "boundary-tetgen");
    cmp.runs.push_back(std::move(r));
  }
  if (do_quality) {
    RunPair r;
    r.name = "quality";
    r.title = "quality";
    r.vdmesh = std::move(quality_vdmesh);
    check_run(r.vdmesh, surface, s, "quality-vdmesh");
    // TetGen's volume bound, for a count near vdmesh's N: first TetGen
    // without a bound (its count N0 then comes from the surface alone); when
    // N0 < 0.8 N, a bound a = 2 V / (N - N0) (V: vdmesh's volume; TetGen's
    // tetrahedra under a bound average about half of it), and once more,
    // scaled by the ratio of the added counts, when the count is still off by
    // more than 25%. The attempt nearest to N is the one reported. Bounds
    // that are too small make TetGen's count (and time) explode, so the
    // estimate errs on the large side.
    long target = 0;
    double volume = 0;
    if (r.vdmesh.checked && r.vdmesh.checks.tets > 0) {
      target = r.vdmesh.checks.tets;
      volume = total_volume(r.vdmesh.checks);
      r.sizing = "tetgen: no volume bound, then a = 2 V / (N - N0) (V, N: vdmesh's volume and count, N0: tetgen's "
                 "count without a bound), rescaled once when the count is off by more than 25%";
    } else if (size > 0) {
      r.sizing = "vdmesh failed: tetgen volume bound a = volume of the regular tetrahedron of edge --size";
    } else {
      r.sizing = "vdmesh failed: tetgen without a volume bound";
    }
    // -q1.414 (radius-edge ratio) does not finish on some inputs with small
    // angles: after a timeout TetGen's default -q (ratio 2) takes over.
    int attempts = 0;
    std::string quality = "q1.414";
    auto attempt = [&](double a) {
      MesherRun t;
      for (;;) {
        const std::string sw = "p" + quality + (a > 0 ? "a" + format_g(a) : std::string()) + "A";
        progress(s, "quality run, tetgen -" + sw);
        ++attempts;
        t = run_tetgen(input, regions, sw,
                       at(attempts == 1 ? "quality-tetgen" : "quality-tetgen-" + std::to_string(attempts)), s.tetgen,
                       s.timeout);
        r.tetgen_attempts.emplace_back("-" + sw, t.meshed ? static_cast<long>(t.mesh.tets.size()) : -1);
        if (!t.process.timed_out || quality == "q") return t;
        quality = "q";
        r.sizing += (r.sizing.empty() ? "" : "; ") + std::string("-q1.414 timed out: -q (ratio 2) instead");
      }
    };
    auto off = [&](const MesherRun& t) {
      return t.meshed ? std::abs(std::log(double(t.mesh.tets.size()) / target)) : HUGE_VAL;
    };
    MesherRun best = attempt(target > 0 || size <= 0 ? 0.0 : size * size * size / (6.0 * std::sqrt(2.0)));
    if (target > 0 && best.meshed) {
      const double n0 = static_cast<double>(best.mesh.tets.size());
      if (n0 < 0.8 * target) {
        const double a1 = 2.0 * volume / (target - n0);
        MesherRun second = attempt(a1);
        if (second.meshed) {
          const double n1 = static_cast<double>(second.mesh.tets.size());
          if (off(second) > std::log(1.25) && n1 > n0) {
            MesherRun third = attempt(a1 * (n1 - n0) / (target - n0));
            if (off(third) < off(second)) second = std::move(third);
          }
          if (off(second) < off(best)) best = std::move(second);
        }
      }
    }
    r.tetgen.run = std::move(best);
    check_run(r.tetgen, surface, s, "quality-tetgen");
    cmp.runs.push_back(std::move(r));
  }

  throw_if_stopped();
  std::fputs(comparison_table(cmp).c_str(), stdout);
  if (!json_path.empty()) write_text(json_path, comparison_json(cmp));
  if (!svg_path.empty())
    write_text(svg_path, histogram_svg("vdmesh and TetGen: " + std::filesystem::path(pos[0]).filename().string(),
                                       histogram_panels(cmp)));
  for (const RunPair& r : cmp.runs)
    if (const int code = vdmesh_exit(r.vdmesh)) return code;
  return 0;
}

}  // namespace vd::app
