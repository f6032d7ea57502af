// TetGen on the same input, in its own process: the surface is written as a
// .smesh (facet markers = face id + 1, so that no facet has marker 0, and the
// region points of a region-tagged input with their region ids as
// attributes), the Debian `tetgen` program runs on it with a time limit, and
// its .node/.ele/.face are read back through the converters (face ids =
// marker - 1, regions = the -A attribute). An abort, crash or timeout is a
// failed run, reported with the end of TetGen's output.
#pragma once

#include <string>
#include <vector>

#include "compare/child_process.h"
#include "compare/mesh_checks.h"
#include "mesh/mesh.h"

namespace vd::compare {

// One mesher's run as compare reports it.
struct MesherRun {
  std::string mesher;        // "vdmesh" or "tetgen"
  std::string label;         // e.g. "tetgen -pYA"
  std::string command;       // the command line that ran
  std::string log_path;      // its stdout and stderr
  ChildResult process;
  bool meshed = false;       // the output was read back
  std::string failure;       // why not: status and the end of the log
  Mesh mesh;                 // read back
};

// Writes `base`.smesh and runs `program -<switches> base.smesh`; reads
// base.1.node/.ele/.face. `switches` without the dash, e.g. "pYA".
MesherRun run_tetgen(const Mesh& input, const std::vector<RegionPoint>& regions, const std::string& switches,
                     const std::string& base, const std::string& program, double timeout_seconds);

// Writes the .smesh TetGen reads: the converter's .smesh with the region list
// added at its end.
void write_tetgen_input(const Mesh& input, const std::vector<RegionPoint>& regions, const std::string& smesh_path);

}  // namespace vd::compare
