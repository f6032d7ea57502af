// The CAD reader as a plugin of the `vdmesh` program. OpenCASCADE's
// libraries cost every run 21 MiB of resident memory and 30 ms of loading
// even on surface input, a seventh of the peak on a 159k-tetrahedron box;
// so the program loads libvdmesh_cad.so (core/cad with OpenCASCADE) only
// when an input is a CAD file. The plugin takes the mesher from the
// program (exported symbols), so there is one copy of core.
// The Python module and the tests link core/cad directly.
#pragma once

#include <string>

#include "cad/cad_mesher.h"

namespace vd::cad {

// What the plugin offers; the same calls as CadModel::read + mesh_cad and
// CadModel::read + tessellate.
struct CadEntryPoints {
  int abi = 0;  // kCadPluginAbi of the plugin's build
  // kCoreHeaderFingerprint of the plugin's build: the program refuses a
  // plugin built against other core headers (the ABI number is bumped by
  // hand and was not, when Mesh gained a field).
  const char* header_fingerprint = "";
  MeshResult (*mesh_file)(const std::string& path, const CadMeshOptions& options, MeshResult* partial) = nullptr;
  Mesh (*tessellate_file)(const std::string& path, const TessellationOptions& options) = nullptr;
  const char* opencascade_version = "";  // OCC_VERSION_COMPLETE of the plugin's build, for `vdmesh --version`
};

// Bumped when CadEntryPoints changes shape, so that a stale plugin beside a
// newer program is refused before its fields are misread.
constexpr int kCadPluginAbi = 4;

}  // namespace vd::cad

// Exported by libvdmesh_cad.so.
extern "C" const vd::cad::CadEntryPoints* vdmesh_cad_entry_points();
