#include "cad/cad_mesher.h"

namespace vd::cad {

MeshResult mesh_cad(const CadModel& model, const CadMeshOptions& options, MeshResult* partial) {
  if (options.mesh.progress) options.mesh.progress("tessellate CAD faces");
  TessellationOptions topt = options.tessellation;
  topt.size = options.mesh.size.uniform;
  topt.cancel = options.mesh.cancel;
  TessellationStats stats;
  const Mesh surface = model.tessellate(topt, &stats);

  MeshOptions mopt = options.mesh;
  mopt.size.uniform = stats.size;
  const auto geometry = model.geometry();
  if (options.splits_on_geometry) {
    mopt.delaunayzation.geometry = geometry.get();
    mopt.delaunayzation.max_flip_offset = stats.deflection;
  }

  CadInputReport cad;
  cad.used = true;
  cad.units = model.units();
  cad.solids = model.solid_count();
  cad.faces = model.face_count();
  cad.interface_faces = model.interface_face_count();
  cad.size = stats.size;
  cad.size_chosen = stats.size_chosen;
  cad.deflection = stats.deflection;
  cad.angle_deg = stats.angle_deg;
  cad.tessellation_rounds = stats.rounds;
  cad.tessellation_volume_error = stats.volume_error;
  cad.occ_triangles = stats.occ_triangles;
  cad.refine_splits = stats.refine_splits;
  cad.refine_flips = stats.refine_flips;
  cad.border_splits = stats.border_splits;
  cad.collapsed_edges = stats.collapsed_edges;
  cad.surface_facets = static_cast<int>(surface.triangles.size());
  const std::vector<std::pair<std::string, double>> cad_seconds = {
      {"read CAD", model.seconds_read},
      {"fuse solids", model.seconds_fuse},
      {"tessellate", stats.seconds_tessellate},
      {"refine surface", stats.seconds_refine}};

  MeshResult result;
  try {
    result = mesh_surface(surface, mopt, partial);
  } catch (...) {
    if (partial) {
      partial->report.cad = cad;
      partial->report.seconds.insert(partial->report.seconds.begin(), cad_seconds.begin(), cad_seconds.end());
    }
    throw;
  }
  cad.volumes = model.volume_checks(result.mesh);
  cad.areas = model.area_checks(result.mesh);
  result.report.cad = cad;
  result.report.seconds.insert(result.report.seconds.begin(), cad_seconds.begin(), cad_seconds.end());
  return result;
}

}  // namespace vd::cad
