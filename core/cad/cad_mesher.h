// The main job: a CAD part or assembly in, tetrahedra per solid out.
// Tessellates (core/cad), then runs TRIANGULATE (pipeline/mesher.h) with
// split vertices placed on the CAD geometry, and measures the result
// against OpenCASCADE's volumes and areas.
#pragma once

#include "cad/cad_model.h"
#include "pipeline/mesher.h"

namespace vd::cad {

struct CadMeshOptions {
  MeshOptions mesh;                 // mesh.size.uniform: the size (0: chosen from the part)
  TessellationOptions tessellation; // its size is taken from mesh.size.uniform
  bool splits_on_geometry = true;   // false: the paper's planar mid-points
};

MeshResult mesh_cad(const CadModel& model, const CadMeshOptions& options, MeshResult* partial = nullptr);

}  // namespace vd::cad
