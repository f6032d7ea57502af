// An SVG of dihedral-angle histograms side by side: one panel per mesher and
// run, all on the same scale (share of all angles per 2-degree bin), with the
// smallest and largest angle marked.
#pragma once

#include <array>
#include <string>
#include <vector>

namespace vd::compare {

struct HistogramPanel {
  std::string title;               // "vdmesh --no-interior"
  bool has_data = false;           // false: the run failed; `note` says why
  std::string note;
  std::array<long, 90> bins{};     // counts of angles in [2i, 2i+2) degrees
  double min_deg = 0, max_deg = 0;
  long tets = 0;
};

// Panels in rows of `columns`, under `title`.
std::string histogram_svg(const std::string& title, const std::vector<HistogramPanel>& panels, int columns = 2);

}  // namespace vd::compare
