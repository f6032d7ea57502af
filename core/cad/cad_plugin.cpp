#include "cad/cad_plugin.h"

#include <Standard_Version.hxx>

#include "cad/cad_model.h"
#include "cad/header_fingerprint.h"

namespace vd::cad {

namespace {

MeshResult mesh_file(const std::string& path, const CadMeshOptions& options, MeshResult* partial) {
  return mesh_cad(CadModel::read(path, options.mesh.cancel, options.fuse), options, partial);
}

Mesh tessellate_file(const std::string& path, const TessellationOptions& options) {
  return CadModel::read(path).tessellate(options);
}

}  // namespace
}  // namespace vd::cad

extern "C" const vd::cad::CadEntryPoints* vdmesh_cad_entry_points() {
  static const vd::cad::CadEntryPoints entry{vd::cad::kCadPluginAbi, kCoreHeaderFingerprint, vd::cad::mesh_file,
                                             vd::cad::tessellate_file, OCC_VERSION_COMPLETE};
  return &entry;
}
