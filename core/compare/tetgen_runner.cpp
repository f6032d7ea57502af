#include "compare/tetgen_runner.h"

#include <cstdio>
#include <filesystem>

#include "converters/registry.h"
#include "mesh/error.h"

namespace vd::compare {

void write_tetgen_input(const Mesh& input, const std::vector<RegionPoint>& regions, const std::string& smesh_path) {
  Mesh surface;
  surface.points = input.points;
  surface.triangles = input.triangles;
  surface.region_points = regions;
  for (Triangle& t : surface.triangles) t.face = t.face < 0 ? 0 : t.face + 1;
  io::write_mesh(surface, smesh_path, {}, "tetgen-plc");
}

MesherRun run_tetgen(const Mesh& input, const std::vector<RegionPoint>& regions, const std::string& switches,
                     const std::string& base, const std::string& program, double timeout_seconds) {
  MesherRun run;
  run.mesher = "tetgen";
  run.label = "tetgen -" + switches;
  run.log_path = base + ".log";
  const std::string smesh = base + ".smesh";
  write_tetgen_input(input, regions, smesh);
  // Outputs of an earlier run under the same name must not pass for this one's.
  for (const char* ext : {".1.node", ".1.ele", ".1.face", ".1.edge"}) std::remove((base + ext).c_str());
  // TetGen prints its error messages with printf and then aborts: through a
  // file they would stay in its stdio buffer, so its stdout is line-buffered
  // (stdbuf execs TetGen in the same process: the measurements are TetGen's).
  std::vector<std::string> argv = {program, "-" + switches, smesh};
  std::error_code ec;
  if (std::filesystem::exists("/usr/bin/stdbuf", ec)) argv.insert(argv.begin(), {"/usr/bin/stdbuf", "-oL"});
  for (const auto& a : argv) run.command += (run.command.empty() ? "" : " ") + a;
  run.process = run_child(argv, run.log_path, timeout_seconds);
  if (!run.process.ok()) {
    run.failure = failure_text(run.process, run.log_path);
    return run;
  }
  try {
    run.mesh = io::read_mesh(base + ".1.node", "tetgen");
  } catch (const std::exception& e) {
    run.failure = std::string("output not readable: ") + e.what();
    return run;
  }
  for (Triangle& t : run.mesh.triangles) t.face -= 1;
  if (run.mesh.tets.empty()) {
    run.failure = "no tetrahedra in the output";
    return run;
  }
  run.meshed = true;
  return run;
}

}  // namespace vd::compare
