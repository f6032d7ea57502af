// Finds and loads libvdmesh_cad.so for the program (core/cad/cad_plugin.h).
#pragma once

#include "cad/cad_plugin.h"

namespace vd::app {

// The plugin's entry points, loaded on the first call from
// <program's folder>/../lib/vdmesh/libvdmesh_cad.so (the build tree and an
// installed prefix alike). Throws std::runtime_error naming the file and
// the loader's reason when it is missing or of another build.
const cad::CadEntryPoints& cad_plugin();

}  // namespace vd::app
