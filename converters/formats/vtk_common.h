// What the legacy .vtk and XML .vtu formats share: cell types, the cell data
// arrays vdmesh writes (region, face, front, back) and the assembly of a Mesh
// from VTK cells.
#pragma once

#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "mesh/mesh.h"

namespace vd::io::detail {

constexpr int kVtkTriangle = 5, kVtkTet = 10, kVtkQuadraticTriangle = 22, kVtkQuadraticTet = 24;

struct VtkCells {
  std::vector<int64_t> offsets;  // size cells + 1; cell i is conn[offsets[i] .. offsets[i+1])
  std::vector<int64_t> conn;
  std::vector<int> types;
  std::map<std::string, std::vector<double>> data;  // cell data arrays (first component)
};

// Cells of `m` in the order the writers use: tetrahedra, then triangles.
VtkCells vtk_cells(const Mesh& m);

// Builds the mesh; errors name `where` (no line: the arrays are checked
// after parsing). Unknown cell types are skipped, bad sizes rejected.
Mesh mesh_from_vtk(std::vector<Vec3> points, const VtkCells& cells, const std::string& where);

}  // namespace vd::io::detail
