#include "compare/compare_report.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>

#include "mesh/number_text.h"

namespace vd::compare {
namespace {

std::string json_string(const std::string& s) {
  std::string out = "\"";
  for (unsigned char c : s) {
    if (c == '"') out += "\\\"";
    else if (c == '\\') out += "\\\\";
    else if (c == '\n') out += "\\n";
    else if (c == '\t') out += "\\t";
    else if (c < 0x20) {
      char b[8];
      std::snprintf(b, sizeof b, "\\u%04x", c);
      out += b;
    } else out += static_cast<char>(c);
  }
  return out + "\"";
}

// Every digit: with 9, a region volume of 0.3333333333333334 read back as
// 0.333333333 differed from the mesh's own sum by just over 1e-9.
std::string num(double x) { return std::isfinite(x) ? number_text(x, "%.17g") : "null"; }

const char* boolean(bool b) { return b ? "true" : "false"; }

template <class Range>
std::string array(const Range& r) {
  std::ostringstream s;
  s << "[";
  bool first = true;
  for (const auto& x : r) s << (first ? "" : ", ") << x, first = false;
  return s.str() + "]";
}

std::string status_word(const CheckedRun& r) {
  if (!r.run.process.started && r.run.failure.empty() && r.run.mesher.empty()) return "not run";
  if (!r.run.meshed) return "FAILED";
  return r.passed() ? "ok" : "CHECKS FAIL";
}

std::string mesher_json(const CheckedRun& r, const std::string& indent) {
  std::ostringstream s;
  const auto& p = r.run.process;
  const auto& c = r.checks;
  const auto& q = c.quality;
  const std::string in = indent + "  ";
  s << "{\n";
  s << in << "\"mesher\": " << json_string(r.run.mesher) << ",\n";
  s << in << "\"label\": " << json_string(r.run.label) << ",\n";
  s << in << "\"command\": " << json_string(r.run.command) << ",\n";
  s << in << "\"status\": " << json_string(p.status()) << ",\n";
  s << in << "\"meshed\": " << boolean(r.run.meshed) << ",\n";
  s << in << "\"failure\": " << json_string(r.run.failure) << ",\n";
  s << in << "\"passed_checks\": " << boolean(r.passed()) << ",\n";
  s << in << "\"seconds\": " << num(p.wall_seconds) << ", \"cpu_seconds\": " << num(p.cpu_seconds)
    << ", \"peak_memory_mib\": " << num(p.peak_rss_mib) << ",\n";
  s << in << "\"log\": " << json_string(r.run.log_path) << ",\n";
  if (!r.mesh_file.empty()) s << in << "\"mesh_file\": " << json_string(r.mesh_file) << ",\n";
  if (r.checked) {
    s << in << "\"vertices\": " << c.vertices << ", \"tetrahedra\": " << c.tets << ", \"boundary_faces\": "
      << c.boundary_faces << ", \"boundary_vertices\": " << c.boundary_vertices
      << ", \"boundary_vertices_added\": " << c.boundary_vertices_added << ",\n";
    s << in << "\"min_dihedral_deg\": " << num(q.min_dihedral_deg) << ", \"max_dihedral_deg\": "
      << num(q.max_dihedral_deg) << ", \"min_radius_ratio\": " << num(q.min_radius_ratio)
      << ", \"mean_radius_ratio\": " << num(q.mean_radius_ratio) << ",\n";
    s << in << "\"slivers_below_5_deg\": " << q.below_5_deg << ", \"slivers_below_10_deg\": " << q.below_10_deg
      << ",\n";
    s << in << "\"dihedral_histogram_10deg\": " << array(q.dihedral_histogram) << ",\n";
    s << in << "\"radius_ratio_histogram_0.1\": " << array(q.radius_ratio_histogram) << ",\n";
    s << in << "\"dihedral_histogram_2deg\": " << array(c.dihedral_histogram_2deg) << ",\n";
    s << in << "\"checks\": {\n";
    const std::string in2 = in + "  ";
    s << in2 << "\"valid\": " << boolean(c.valid()) << ", \"inverted\": " << c.inverted
      << ", \"non_manifold_faces\": " << c.non_manifold_faces << ",\n";
    s << in2 << "\"conforming\": " << boolean(c.conforming()) << ", \"boundary_faces_off_input\": "
      << c.boundary_faces_off_input << ", \"input_facets_uncovered\": " << c.input_facets_uncovered
      << ", \"degenerate_input_facets\": " << c.degenerate_input_facets << ",\n";
    s << in2 << "\"max_distance_to_input\": " << num(c.max_distance_to_input) << ", \"max_distance_to_output\": "
      << num(c.max_distance_to_output) << ", \"distance_unit\": \"input bounding-box diagonal\", "
      << "\"tolerance\": \"" << kConformityTolerance << " x longest edge\",\n";
    s << in2 << "\"tags_ok\": " << boolean(c.tags_ok()) << ", \"boundary_faces_untagged\": "
      << c.boundary_faces_untagged << ", \"face_ids_wrong\": " << c.face_ids_wrong
      << ", \"region_tags_checked\": " << boolean(c.region_tags_checked) << ", \"facet_sides_wrong\": "
      << c.facet_sides_wrong << ", \"facet_sides_ambiguous\": " << c.facet_sides_ambiguous << ",\n";
    s << in2 << "\"volumes_ok\": " << boolean(c.volumes_ok(kVolumeTolerance)) << ", \"volume_tolerance\": "
      << num(kVolumeTolerance) << ", \"max_relative_volume_error\": " << num(c.max_relative_volume_error)
      << ", \"volume_reference\": " << json_string(c.volume_reference) << ",\n";
    s << in2 << "\"regions\": [";
    for (size_t i = 0; i < c.regions.size(); ++i) {
      const auto& g = c.regions[i];
      s << (i ? ", " : "") << "{\"region\": " << g.region << ", \"tetrahedra\": " << g.tets
        << ", \"volume\": " << num(g.volume) << ", \"reference\": " << num(g.reference)
        << ", \"relative_error\": " << num(g.relative_error) << "}";
    }
    s << "],\n";
    s << in2 << "\"problems\": [";
    const auto problems = c.problems(kVolumeTolerance);
    for (size_t i = 0; i < problems.size(); ++i) s << (i ? ", " : "") << json_string(problems[i]);
    s << "]\n" << in << "}";
  } else {
    s << in << "\"checks\": null";
  }
  if (!r.report_json.empty()) {
    std::string rep = r.report_json;
    while (!rep.empty() && (rep.back() == '\n' || rep.back() == ' ')) rep.pop_back();
    s << ",\n" << in << "\"report\": " << rep;
  }
  s << "\n" << indent << "}";
  return s.str();
}

std::string cell(const CheckedRun& r, const std::string& text) { return r.checked ? text : "-"; }

std::string f(const char* format, double x) { return number_text(x, format); }

}  // namespace

std::string comparison_json(const Comparison& c) {
  std::ostringstream s;
  s << "{\n";
  s << "  \"input\": " << json_string(c.input) << ",\n";
  s << "  \"input_vertices\": " << c.input_vertices << ", \"input_facets\": " << c.input_facets
    << ", \"face_patches_assigned\": " << c.face_patches << ", \"region_tags\": " << boolean(c.region_tags)
    << ", \"region_points_for_tetgen\": " << c.region_points << ",\n";
  s << "  \"size\": " << num(c.size) << ", \"tetgen_program\": " << json_string(c.tetgen_program)
    << ", \"timeout_seconds\": " << num(c.timeout_seconds) << ",\n";
  s << "  \"cad_tessellation\": " << json_string(c.tessellation) << ", \"cad_tessellations_given_up\": [";
  for (size_t i = 0; i < c.tessellations_given_up.size(); ++i)
    s << (i ? ", " : "") << json_string(c.tessellations_given_up[i]);
  s << "],\n";
  s << "  \"work_dir\": " << json_string(c.kept ? c.work_dir : "") << ",\n";
  s << "  \"measurement\": \"each mesher runs in its own process (vdmesh: this program's compare worker); seconds are "
       "wall clock from start to exit, including reading the input and writing the output; memory is the "
       "child's peak resident set (wait4 ru_maxrss)\",\n";
  s << "  \"runs\": [\n";
  for (size_t i = 0; i < c.runs.size(); ++i) {
    const RunPair& r = c.runs[i];
    s << "    {\n      \"name\": " << json_string(r.name) << ", \"title\": " << json_string(r.title) << ",\n";
    s << "      \"sizing\": " << json_string(r.sizing) << ",\n";
    s << "      \"tetgen_attempts\": [";
    for (size_t a = 0; a < r.tetgen_attempts.size(); ++a)
      s << (a ? ", " : "") << "{\"switches\": " << json_string(r.tetgen_attempts[a].first)
        << ", \"tetrahedra\": " << r.tetgen_attempts[a].second << "}";
    s << "],\n";
    s << "      \"vdmesh\": " << mesher_json(r.vdmesh, "      ") << ",\n";
    s << "      \"tetgen\": " << mesher_json(r.tetgen, "      ") << "\n";
    s << "    }" << (i + 1 < c.runs.size() ? "," : "") << "\n";
  }
  s << "  ]\n}\n";
  return s.str();
}

std::string comparison_table(const Comparison& c) {
  std::ostringstream s;
  s << "vdmesh compare: " << c.input << " (" << c.input_vertices << " vertices, " << c.input_facets << " facets"
    << (c.region_tags ? ", region tags" : "") << (c.face_patches > 0 ? ", face ids from sharp edges" : "") << ")\n";
  if (!c.tessellation.empty()) {
    s << "  CAD tessellation: " << c.tessellation;
    for (size_t i = 0; i < c.tessellations_given_up.size(); ++i)
      s << (i ? "; " : " (given up before: ") << c.tessellations_given_up[i];
    s << (c.tessellations_given_up.empty() ? "" : ")") << "\n";
  }
  // Columns: the quantity, then vdmesh and TetGen of each run.
  std::vector<const CheckedRun*> cols;
  std::vector<std::string> head1, head2;
  for (const RunPair& r : c.runs) {
    cols.push_back(&r.vdmesh);
    cols.push_back(&r.tetgen);
    head1.push_back(r.title);
    head1.push_back("");
    head2.push_back(r.vdmesh.run.label);
    head2.push_back(r.tetgen.run.label);
  }
  std::vector<std::pair<std::string, std::vector<std::string>>> rows;
  auto row = [&](const std::string& name, auto value) {
    std::vector<std::string> v;
    for (const CheckedRun* r : cols) v.push_back(value(*r));
    rows.emplace_back(name, v);
  };
  row("result", [](const CheckedRun& r) { return status_word(r); });
  row("time s (cpu s)", [](const CheckedRun& r) {
    return r.run.process.started ? f("%.2f", r.run.process.wall_seconds) + f(" (%.2f)", r.run.process.cpu_seconds)
                                 : std::string("-");
  });
  row("peak memory MiB", [](const CheckedRun& r) {
    return r.run.process.started ? f("%.1f", r.run.process.peak_rss_mib) : std::string("-");
  });
  row("vertices", [](const CheckedRun& r) { return cell(r, std::to_string(r.checks.vertices)); });
  row("tetrahedra", [](const CheckedRun& r) { return cell(r, std::to_string(r.checks.tets)); });
  row("boundary vertices added",
      [](const CheckedRun& r) { return cell(r, std::to_string(r.checks.boundary_vertices_added)); });
  row("smallest dihedral deg",
      [](const CheckedRun& r) { return cell(r, f("%.2f", r.checks.quality.min_dihedral_deg)); });
  row("largest dihedral deg",
      [](const CheckedRun& r) { return cell(r, f("%.2f", r.checks.quality.max_dihedral_deg)); });
  row("radius ratio min / mean", [](const CheckedRun& r) {
    return cell(r, f("%.3f", r.checks.quality.min_radius_ratio) + f(" / %.3f", r.checks.quality.mean_radius_ratio));
  });
  row("slivers <5 / <10 deg", [](const CheckedRun& r) {
    return cell(r, std::to_string(r.checks.quality.below_5_deg) + " / " + std::to_string(r.checks.quality.below_10_deg));
  });
  row("inverted", [](const CheckedRun& r) { return cell(r, std::to_string(r.checks.inverted)); });
  row("regions (max vol. error)", [](const CheckedRun& r) {
    return cell(r, std::to_string(r.checks.regions.size()) + f(" (%.1e)", r.checks.max_relative_volume_error));
  });
  row("boundary off input / uncov.", [](const CheckedRun& r) {
    return cell(r, std::to_string(r.checks.boundary_faces_off_input) + " / " +
                       std::to_string(r.checks.input_facets_uncovered));
  });
  row("max deviation / diagonal", [](const CheckedRun& r) {
    return cell(r, f("%.1e", std::max(r.checks.max_distance_to_input, r.checks.max_distance_to_output)));
  });
  row("face ids / sides wrong", [](const CheckedRun& r) {
    return cell(r, std::to_string(r.checks.face_ids_wrong + r.checks.boundary_faces_untagged) + " / " +
                       (r.checks.region_tags_checked ? std::to_string(r.checks.facet_sides_wrong) : std::string("n/a")));
  });

  size_t w0 = 10;
  for (const auto& r : rows) w0 = std::max(w0, r.first.size());
  std::vector<size_t> w(cols.size(), 8);
  for (size_t i = 0; i < cols.size(); ++i) {
    w[i] = std::max({w[i], head2[i].size(), (i % 2 == 0 ? head1[i].size() : size_t{0}) / 2});
    for (const auto& r : rows) w[i] = std::max(w[i], r.second[i].size());
  }
  auto line = [&](const std::string& name, const std::vector<std::string>& v) {
    s << "  " << name << std::string(w0 - name.size(), ' ');
    for (size_t i = 0; i < v.size(); ++i) s << "  " << v[i] << std::string(w[i] - std::min(w[i], v[i].size()), ' ');
    s << "\n";
  };
  {
    // Run titles spanning their two columns.
    s << "  " << std::string(w0, ' ');
    for (size_t i = 0; i < cols.size(); i += 2) {
      const size_t span = w[i] + 2 + w[i + 1];
      std::string t = head1[i].substr(0, span);
      s << "  " << t << std::string(span - t.size(), ' ');
    }
    s << "\n";
  }
  line("", head2);
  for (const auto& r : rows) line(r.first, r.second);
  // Failures and failed checks in words.
  for (const RunPair& r : c.runs) {
    if (!r.sizing.empty()) s << "  " << r.name << ": " << r.sizing << "\n";
    for (const CheckedRun* m : {&r.vdmesh, &r.tetgen}) {
      if (!m->run.meshed && !m->run.failure.empty())
        s << "  " << r.name << ", " << m->run.label << " failed: " << m->run.failure << "\n";
      if (m->checked)
        for (const auto& p : m->checks.problems(kVolumeTolerance))
          s << "  " << r.name << ", " << m->run.label << ": " << p << "\n";
    }
  }
  return s.str();
}

std::vector<HistogramPanel> histogram_panels(const Comparison& c) {
  std::vector<HistogramPanel> out;
  for (const RunPair& r : c.runs)
    for (const CheckedRun* m : {&r.vdmesh, &r.tetgen}) {
      HistogramPanel p;
      p.title = r.title + ": " + m->run.label;
      p.has_data = m->checked && m->checks.tets > 0;
      if (p.has_data) {
        p.bins = m->checks.dihedral_histogram_2deg;
        p.min_deg = m->checks.quality.min_dihedral_deg;
        p.max_deg = m->checks.quality.max_dihedral_deg;
        p.tets = m->checks.tets;
      } else {
        p.note = "failed: " + m->run.failure;
      }
      out.push_back(p);
    }
  return out;
}

}  // namespace vd::compare
