// The report of a run: JSON for --report, and the short table printed at the end.
#include <cmath>
#include <cstdio>
#include <sstream>

#include "mesh/number_text.h"
#include "pipeline/mesher.h"

namespace vd {
namespace {

template <class Range>
std::string json_array(const Range& r) {
  std::ostringstream s;
  s << "[";
  bool first = true;
  for (const auto& x : r) s << (first ? "" : ", ") << x, first = false;
  s << "]";
  return s.str();
}

// Six digits for the table; every digit in the JSON, where a volume error of
// 1e-6 must still show.
std::string num(double x) { return number_text(x); }

std::string exact(double x) { return number_text(x, "%.17g"); }

}  // namespace

std::string report_json(const MeshReport& r) {
  std::ostringstream s;
  const auto& o = r.oracle_stats;
  const auto& d = r.delaunayzation;
  const auto& q = r.quality;
  s << "{\n";
  s << "  \"complete\": " << (r.complete ? "true" : "false") << ",\n";
  if (!r.allocator.empty()) s << "  \"allocator\": \"" << r.allocator << "\",\n";
  s << "  \"counts\": {\"input_vertices\": " << r.input_vertices << ", \"input_facets\": " << r.input_facets
    << ", \"unused_input_vertices\": " << r.unused_input_vertices
    << ", \"welded_input_vertices\": " << r.welded_input_vertices
    << ", \"output_vertices\": " << r.output_vertices << ", \"output_facets\": " << r.output_facets
    << ", \"added_surface_vertices\": " << r.added_surface_vertices
    << ", \"added_surface_facets\": " << r.added_surface_facets
    << ", \"hole_facets_dropped\": " << r.hole_facets_dropped
    << ", \"face_patches_assigned\": " << r.face_patches_assigned << ", \"size_splits\": " << r.size_splits << ", \"size_flips\": " << r.size_flips << ", \"tetrahedra\": " << q.tets
    << ", \"tets_per_region\": " << json_array(r.tets_per_region) << ", \"regions\": " << r.regions.regions
    << ", \"regions_from_tags\": " << (r.regions.regions_from_tags ? "true" : "false") << "},\n";
  s << "  \"oracle\": {\"name\": \"" << r.oracle << "\", \"queries\": " << o.queries << ", \"delaunay\": " << o.delaunay
    << ", \"by_tetrahedralization\": " << o.by_tetrahedralization << ", \"by_stored_apex\": " << o.by_stored_apex
    << ", \"by_equatorial_sphere\": " << o.by_equatorial_sphere << ", \"by_candidate_apex\": " << o.by_candidate_apex
    << ", \"by_lp\": " << o.by_lp << ", \"lp_solved\": " << o.lp_solved << ", \"lp_average_size\": "
    << exact(o.lp_solved ? double(o.lp_unknowns) / o.lp_solved : 0.0) << ", \"lp_refused_by_limit\": "
    << o.lp_refused_by_limit << ", \"lp_ambiguous\": " << o.lp_ambiguous << ", \"wrong_answers_caught\": "
    << d.oracle_wrong << "},\n";
  s << "  \"delaunayzation\": {\"passes\": " << d.passes << ", \"flips\": " << d.flips << ", \"splits\": " << d.splits
    << ", \"splits_on_chord\": " << d.splits_on_chord << ", \"splits_on_chord_for_volume\": " << d.splits_on_chord_for_volume
    << ", \"added_vertices\": " << d.added_vertices << ", \"added_facets\": " << d.added_facets
    << ", \"shell_splits\": " << (d.shell_splits ? "true" : "false") << "},\n";
  s << "  \"interior\": {\"vertices\": " << r.interior_vertices << ", \"offset_points\": " << r.interior.offset_points
    << ", \"lattice_points\": " << r.interior.lattice_points << ", \"candidates\": " << r.interior.candidates
    << ", \"rejected_outside\": " << r.interior.rejected_outside << ", \"rejected_near_vertex\": "
    << r.interior.rejected_near_vertex << ", \"rejected_near_surface\": " << r.interior.rejected_near_surface
    << ", \"cap_points\": " << r.interior.cap_points << ", \"cap_points_refused\": " << r.interior.cap_points_refused
    << ", \"cap_points_fallback\": " << r.interior.cap_points_fallback
    << ", \"cap_folds_split\": " << r.interior.cap_folds_split
    << ", \"cap_folds_at_sharp_corners\": " << r.interior.cap_folds_at_sharp_corners
    << ", \"cap_fold_round_undone\": " << (r.interior.cap_fold_round_undone ? "true" : "false")
    << ", \"rejected_taking_a_facet\": " << r.interior.rejected_taking_a_facet
    << ", \"cautious_retry\": " << (r.interior.cautious_retry ? "true" : "false")
    << ", \"smallest_size\": " << exact(r.smallest_size) << "},\n";
  if (r.advancing_front)
    s << "  \"advancing_front\": {\"front_faces\": " << r.front.front_faces << ", \"candidates\": "
      << r.front.candidates << ", \"searches\": " << r.front.searches << ", \"ties\": " << r.front.ties << "},\n";
  const auto& sl = r.slivers;
  s << "  \"slivers\": {\"angle_deg\": " << exact(sl.angle_deg) << ", \"raised_to_deg\": " << exact(sl.raised_to_deg)
    << ", \"raised_changes\": " << sl.raised_changes
    << ", \"raised_allowance_used\": " << (sl.raised_allowance_used ? "true" : "false")
    << ", \"before\": " << sl.slivers_before << ", \"removed_boundary\": " << sl.removed_boundary
    << ", \"removed_across_ridges\": " << sl.removed_across_ridges
    << ", \"removed_crease_caps\": " << sl.removed_crease_caps
    << ", \"flips_23\": " << sl.flips_23 << ", \"flips_32\": " << sl.flips_32
    << ", \"edge_removals\": " << sl.edge_removals << ", \"insertions\": " << sl.insertions
    << ", \"moves\": " << sl.moves
    << ", \"surface_moves\": " << sl.surface_moves << ", \"held_moves\": " << sl.held_moves
    << ", \"delaunay_surface\": " << (sl.delaunay_surface ? "true" : "false")
    << ", \"moves_blocked\": " << sl.moves_blocked << ", \"after\": " << sl.slivers_after
    << ", \"min_dihedral_before_deg\": " << exact(sl.min_dihedral_before_deg)
    << ", \"min_dihedral_after_deg\": " << exact(sl.min_dihedral_after_deg)
    << ", \"tets_below_5_deg_before\": " << sl.below_5_before << ", \"tets_below_10_deg_before\": "
    << sl.below_10_before << ", \"tets_below_5_deg_after\": " << sl.below_5_after
    << ", \"tets_below_10_deg_after\": " << sl.below_10_after << "},\n";
  s << "  \"shift\": {\"free\": " << r.shift.moved_free << ", \"in_plane\": " << r.shift.moved_in_plane
    << ", \"on_edge\": " << r.shift.moved_on_edge << ", \"fixed\": " << r.shift.fixed
    << ", \"restored\": " << r.shift.restored << "},\n";
  s << "  \"seconds\": {";
  for (size_t i = 0; i < r.seconds.size(); ++i)
    s << (i ? ", " : "") << "\"" << r.seconds[i].first << "\": " << exact(r.seconds[i].second);
  s << "},\n";
  s << "  \"peak_mib\": {";
  for (size_t i = 0; i < r.peak_mib.size(); ++i)
    s << (i ? ", " : "") << "\"" << r.peak_mib[i].first << "\": " << exact(r.peak_mib[i].second);
  s << "},\n";
  s << "  \"quality\": {\"tetrahedra\": " << q.tets << ", \"inverted\": " << q.inverted
    << ", \"min_dihedral_deg\": " << exact(q.min_dihedral_deg) << ", \"max_dihedral_deg\": " << exact(q.max_dihedral_deg)
    << ", \"min_radius_ratio\": " << exact(q.min_radius_ratio) << ", \"mean_radius_ratio\": " << exact(q.mean_radius_ratio)
    << ", \"tets_below_5_deg\": " << q.below_5_deg << ", \"tets_below_10_deg\": " << q.below_10_deg
    << ", \"dihedral_histogram_10deg\": " << json_array(q.dihedral_histogram)
    << ", \"radius_ratio_histogram_0.1\": " << json_array(q.radius_ratio_histogram) << "},\n";
  if (r.second_order.nodes > 0) {
    const auto& so = r.second_order;
    s << "  \"second_order\": {\"nodes\": " << so.nodes << ", \"surface_nodes\": " << so.surface_nodes
      << ", \"on_geometry\": " << so.on_geometry << ", \"kept_straight\": " << so.kept_straight
      << ", \"min_scaled_jacobian\": " << exact(so.min_scaled_jacobian) << "},\n";
  }
  if (r.cad.used) {
    const auto& c = r.cad;
    auto measures = [&](const std::vector<ReferenceMeasure>& v) {
      std::ostringstream a;
      a << "[";
      for (size_t i = 0; i < v.size(); ++i)
        a << (i ? ", " : "") << "{\"name\": \"" << v[i].name << "\", \"cad\": " << exact(v[i].reference)
          << ", \"mesh\": " << exact(v[i].mesh) << "}";
      a << "]";
      return a.str();
    };
    s << "  \"cad\": {\"units\": \"" << c.units << "\", \"solids\": " << c.solids << ", \"faces\": " << c.faces
      << ", \"interface_faces\": " << c.interface_faces << ", \"fuse\": \"" << c.fuse << "\""
      << ", \"size\": " << exact(c.size)
      << ", \"size_chosen\": " << (c.size_chosen ? "true" : "false") << ", \"thin_faces\": " << c.thin_faces
      << ", \"thin_size\": " << exact(c.thin_size) << ", \"thinnest_solid\": " << exact(c.thinnest)
      << ", \"deflection\": " << exact(c.deflection)
      << ", \"angular_deflection_deg\": " << exact(c.angle_deg) << ", \"tessellation_rounds\": " << c.tessellation_rounds
      << ", \"recovery_retries\": " << c.recovery_retries << ", \"recovery_runaways\": " << c.recovery_runaways
      << ", \"held_solids\": " << json_array(c.held_solids)
      << ", \"tessellation_volume_error\": " << exact(c.tessellation_volume_error)
      << ", \"occ_triangles\": " << c.occ_triangles
      << ", \"refine_splits\": " << c.refine_splits << ", \"refine_flips\": " << c.refine_flips
      << ", \"border_splits\": " << c.border_splits << ", \"collapsed_edges\": " << c.collapsed_edges
      << ", \"flat_vertices_removed\": " << c.flat_vertices_removed
      << ", \"border_caps_snapped\": " << c.border_caps_snapped
      << ", \"needle_edges_collapsed\": " << c.needle_edges_collapsed
      << ", \"smoothing_moves\": " << c.smoothing_moves << ", \"remeshed_faces\": " << c.remeshed_faces
      << ", \"smoothing_dropped\": " << (c.smoothing_dropped ? "true" : "false")
      << ", \"remeshing_dropped\": " << (c.remeshing_dropped ? "true" : "false")
      << ", \"planar_splits_fallback\": " << (c.planar_splits_fallback ? "true" : "false")
      << ", \"surface_facets\": " << c.surface_facets << ",\n    \"volumes\": " << measures(c.volumes)
      << ",\n    \"areas\": " << measures(c.areas) << ",\n    \"overlaps\": [";
    for (size_t i = 0; i < c.overlaps.size(); ++i)
      s << (i ? ", " : "") << "{\"solids\": " << json_array(c.overlaps[i].solids)
        << ", \"volume\": " << exact(c.overlaps[i].volume) << "}";
    s << "]},\n";
  }
  s << "  \"missing_facets\": [";
  for (size_t i = 0; i < r.missing_facets.size(); ++i) s << (i ? ", " : "") << json_array(r.missing_facets[i]);
  s << "]\n}\n";
  return s.str();
}

std::string report_table(const MeshReport& r) {
  std::ostringstream s;
  const auto& o = r.oracle_stats;
  const auto& q = r.quality;
  // No fixed buffer: the seconds row of a CAD run is longer than 256
  // characters, and it was cut, newline and all.
  auto row = [&](const char* name, const std::string& value) {
    std::string label = name;
    if (label.size() < 28) label.resize(28, ' ');
    s << "  " << label << " " << value << "\n";
  };
  s << "vdmesh report\n";
  if (r.cad.used) {
    const auto& c = r.cad;
    row("CAD", std::to_string(c.solids) + " solids, " + std::to_string(c.faces) + " faces, " +
                   std::to_string(c.interface_faces) + " interfaces; units " + c.units +
                   (c.fuse == "none" ? "" : "; fused " + c.fuse));
    row("size", num(c.size) + (c.size_chosen ? " (chosen: bounding box diagonal / 25)" : " (given)") +
                    (c.thin_faces > 0 ? "; " + std::to_string(c.thin_faces) + " faces of thin solids down to " +
                                            num(c.thin_size) + " (from their mean thickness 2V/A)"
                                      : "") +
                    // The size kept over a thin solid (given, or an assembly's): say what that makes.
                    (c.thin_faces == 0 && c.thinnest > 0 && 4 * c.thinnest < c.size
                         ? "; a solid is " + num(c.thinnest) +
                               " thick (2V/A): tetrahedra across it are flat, give a smaller --size"
                         : "") +
                    ", chord height " + num(c.deflection) + ", angle " + num(c.angle_deg) + " deg");
    row("tessellation", std::to_string(c.occ_triangles) + " OpenCASCADE triangles, " +
                            std::to_string(c.collapsed_edges) + " short edges collapsed, " +
                            std::to_string(c.refine_splits) + " splits, " + std::to_string(c.refine_flips) +
                            " flips, " + std::to_string(c.border_splits) + " border slivers split, " +
                            std::to_string(c.border_caps_snapped) + " border caps snapped, " +
                            std::to_string(c.needle_edges_collapsed) + " needle edges collapsed at poles, " +
                            std::to_string(c.smoothing_moves) + " smoothing moves" +
                            (c.smoothing_dropped ? " (smoothing dropped)" : "") + ", " +
                            std::to_string(c.flat_vertices_removed) + " flat inner vertices removed, " +
                            std::to_string(c.remeshed_faces) + " faces remeshed" +
                            (c.remeshing_dropped ? " (remeshing dropped)" : "") + " -> " + std::to_string(c.surface_facets) + " facets; " +
                            std::to_string(c.tessellation_rounds) + (c.tessellation_rounds > 1 ? " rounds" : " round") +
                            ", volume within " + num(100 * c.tessellation_volume_error) + " %" +
                            (c.held_solids.empty()
                                 ? ""
                                 : " (" + std::to_string(c.held_solids.size()) +
                                       " solids left alone by the rounds: recovery ran away beside them)") +
                            (c.recovery_retries ? "; tessellated again " + std::to_string(c.recovery_retries) +
                                                      (c.recovery_retries > 1 ? " times" : " time") +
                                                      " after recovery stopped" +
                                                      (c.recovery_runaways ? " (" + std::to_string(c.recovery_runaways) +
                                                                                 " ran away)"
                                                                           : "")
                                                : "") +
                            (c.planar_splits_fallback ? "; split vertices on the chords (every recovery with them on "
                                                        "the CAD geometry stopped)"
                                                      : ""));
    // The bound for a solid's mesh volume against its CAD volume.
    constexpr double kVolumeWarning = 0.005;
    double worst = 0;
    std::string which;
    int off = 0;
    for (const auto& v : c.volumes) {
      const double e = v.reference != 0 ? (v.mesh - v.reference) / v.reference : 0.0;
      row(("volume " + v.name).c_str(), "CAD " + num(v.reference) + ", mesh " + num(v.mesh) + " (" +
                                            num(100.0 * e) + " %)");
      if (std::abs(e) > std::abs(worst)) worst = e, which = v.name;
      off += std::abs(e) > kVolumeWarning;
    }
    // Said apart from the rows: on an assembly of 27 solids one 5 % is
    // easily missed (gmsh_simple_plane.brep on its last retry).
    if (off > 0)
      row("volumes off by over 0.5 %", std::to_string(off) + " of " + std::to_string(c.volumes.size()) +
                                          " solids (largest " + which + ", " + num(100.0 * worst) + " %)");
    // An overlap is usually a modelling fault of the assembly: said apart.
    for (const auto& o : c.overlaps) {
      std::string names;
      for (size_t i = 0; i < o.solids.size(); ++i)
        names += (i == 0 ? "" : i + 1 == o.solids.size() ? " and " : ", ") + ("Solid" + std::to_string(o.solids[i]));
      row("overlapping solids", names + " share a volume of " + num(o.volume) + ", meshed as Solid" +
                                    std::to_string(o.solids.front()));
    }
    double worst_area = 0;
    std::string which_area;
    for (const auto& a : c.areas) {
      const double e = a.reference != 0 ? (a.mesh - a.reference) / a.reference : 0.0;
      if (std::abs(e) > std::abs(worst_area)) worst_area = e, which_area = a.name;
    }
    if (!which_area.empty()) row("largest face area error", which_area + " " + num(100.0 * worst_area) + " %");
  }
  row("input", std::to_string(r.input_vertices) + " vertices, " + std::to_string(r.input_facets) + " facets" +
                   (r.unused_input_vertices ? " (" + std::to_string(r.unused_input_vertices) +
                                                  " vertices no facet uses dropped)"
                                            : std::string()) +
                   (r.welded_input_vertices ? " (" + std::to_string(r.welded_input_vertices) +
                                                  " vertices at another's coordinates welded to it)"
                                            : std::string()));
  if (r.size_splits > 0)
    row("split to the size", std::to_string(r.size_splits) + " surface edges, " + std::to_string(r.size_flips) + " flips");
  row("added on the surface", std::to_string(r.added_surface_vertices) + " vertices, " +
                                  std::to_string(r.added_surface_facets) + " facets");
  row("interior vertices", std::to_string(r.interior_vertices));
  row("Delaunayzation", std::to_string(r.delaunayzation.passes) + " passes, " + std::to_string(r.delaunayzation.flips) +
                            " flips, " + std::to_string(r.delaunayzation.splits) + " splits" +
                            (r.delaunayzation.splits_on_chord
                                 ? " (" + std::to_string(r.delaunayzation.splits_on_chord) + " kept on the chord" +
                                       (r.delaunayzation.splits_on_chord_for_volume
                                            ? ", " + std::to_string(r.delaunayzation.splits_on_chord_for_volume) +
                                                  " of them for a solid's volume"
                                            : std::string()) +
                                       ")"
                                 : std::string()) +
                            (r.delaunayzation.shell_splits ? "; edges from corners split on concentric shells" : ""));
  row("oracle", r.oracle + ": " + std::to_string(o.queries) + " queries, " + std::to_string(o.lp_solved) + " LPs");
  std::string per_region;
  for (size_t i = 1; i < r.tets_per_region.size(); ++i)
    per_region += (per_region.empty() ? "" : ", ") + std::string("region ") + std::to_string(i) + ": " +
                  std::to_string(r.tets_per_region[i]);
  row("tetrahedra", std::to_string(q.tets) + (per_region.empty() ? "" : " (" + per_region + ")"));
  row("dihedral angle (deg)", "min " + num(q.min_dihedral_deg) + ", max " + num(q.max_dihedral_deg));
  row("radius ratio", "min " + num(q.min_radius_ratio) + ", mean " + num(q.mean_radius_ratio));
  if (r.advancing_front)
    row("advancing front", std::to_string(r.front.front_faces) + " faces closed, " +
                               std::to_string(r.front.candidates) + " candidates, " + std::to_string(r.front.ties) +
                               " ties");
  const auto& sl = r.slivers;
  row("slivers (A / B / C)", std::to_string(sl.removed_boundary) + " removed" +
                                 (sl.removed_across_ridges > 0
                                      ? " (" + std::to_string(sl.removed_across_ridges) + " across ridges)"
                                      : "") +
                                 (sl.removed_crease_caps > 0
                                      ? " (" + std::to_string(sl.removed_crease_caps) + " over crease facets)"
                                      : "") +
                                 ", " +
                                 std::to_string(sl.flips_23 + sl.flips_32 + sl.edge_removals) + " flips (" +
                                 std::to_string(sl.flips_23) + " 2-3, " + std::to_string(sl.flips_32) + " 3-2, " +
                                 std::to_string(sl.edge_removals) + " edge removals), " +
                                 std::to_string(sl.moves) + " moves, " + std::to_string(sl.insertions) +
                                 " insertions; " + std::to_string(sl.slivers_before) + " -> " + std::to_string(sl.slivers_after) + " slivers" +
                                 (sl.raised_to_deg > 0 ? "; none left, aim raised to " + num(sl.raised_to_deg) + " deg (" +
                                                               std::to_string(sl.raised_changes) + " changes" +
                                                               (sl.raised_allowance_used ? ", the allowance" : "") + ")"
                                                         : ""));
  row("before slivers: min, <5, <10", num(sl.min_dihedral_before_deg) + " deg, " +
                                          std::to_string(sl.below_5_before) + ", " +
                                          std::to_string(sl.below_10_before));
  row("tets under 5 / 10 deg", std::to_string(q.below_5_deg) + " / " + std::to_string(q.below_10_deg));
  if (r.second_order.nodes > 0)
    row("second order", std::to_string(r.second_order.nodes) + " mid-edge nodes, " +
                            std::to_string(r.second_order.on_geometry - r.second_order.kept_straight) +
                            " on the CAD geometry, min scaled Jacobian " + num(r.second_order.min_scaled_jacobian));
  std::string times;
  double total = 0;
  for (const auto& [phase, sec] : r.seconds) {
    times += (times.empty() ? "" : ", ") + phase + " " + num(sec);
    total += sec;
  }
  row("seconds", num(total) + " (" + times + ")");
  return s.str();
}

}  // namespace vd
