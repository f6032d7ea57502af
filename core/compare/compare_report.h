// What `vdmesh compare` found, as a side-by-side table, JSON and SVG panels.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "compare/mesh_checks.h"
#include "compare/svg_histogram.h"
#include "compare/tetgen_runner.h"

namespace vd::compare {

// Region volumes agree with the input when within this relative error.
// TetGen keeps the input's points (errors ~1e-15); vdmesh moves surface
// vertices by up to 1e-4 of the local size within their tangent planes
// (README, random shift), which changes a curved surface's volume by a small
// fraction of that (measured: under 1e-6 on the shared surfaces without
// flips across ridges). Flips within a face across a ridge change it more:
// the checks report that as a failure.
constexpr double kVolumeTolerance = 1e-4;

struct CheckedRun {
  MesherRun run;
  bool checked = false;       // the mesh was read back and checked
  MeshChecks checks;
  std::string report_json;    // vdmesh's own report, when it wrote one
  std::string mesh_file;      // a copy of the mesh (.vtu) in the kept folder
  bool passed() const { return checked && checks.problems(kVolumeTolerance).empty(); }
};

struct RunPair {
  std::string name;           // "boundary" or "quality"
  std::string title;          // for the table
  CheckedRun vdmesh, tetgen;
  std::vector<std::pair<std::string, long>> tetgen_attempts;  // switches, tetrahedra (-1: failed)
  std::string sizing;         // how the TetGen volume bound was chosen
};

struct Comparison {
  std::string input;
  long input_vertices = 0, input_facets = 0;
  int face_patches = 0;       // > 0: face ids given by compare from sharp edges
  bool region_tags = false;
  int region_points = 0;      // given to TetGen
  double size = 0;            // --size (0: vdmesh's default)
  // CAD input: the tessellation both meshers got, and those given up
  // before it (vdmesh's recovery stopped on them), each with its run.
  std::string tessellation;
  std::vector<std::string> tessellations_given_up;
  std::string tetgen_program;
  double timeout_seconds = 0;
  std::string work_dir;
  bool kept = false;
  std::vector<RunPair> runs;
};

std::string comparison_table(const Comparison& c);
std::string comparison_json(const Comparison& c);
std::vector<HistogramPanel> histogram_panels(const Comparison& c);

}  // namespace vd::compare
