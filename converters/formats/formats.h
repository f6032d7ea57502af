// One factory per format file; registry.cpp lists them.
#pragma once

#include "registry.h"

namespace vd::io {

Format make_off_format();
Format make_stl_format();
Format make_obj_format();
Format make_ply_format();
Format make_gmsh_format();
Format make_vtk_format();
Format make_vtu_format();
Format make_pvtu_format();
Format make_tetgen_format();      // .node / .ele / .face
Format make_tetgen_plc_format();  // .poly / .smesh
Format make_medit_format();
Format make_meshb_format();
Format make_abaqus_format();

}  // namespace vd::io
