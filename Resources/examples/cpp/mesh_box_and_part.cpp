// Meshes a box given as a tagged surface, then a CAD file, with the vdmesh
// library, and writes both meshes:
//   mesh_box_and_part BOX_OUT PART.{step,iges,brep} PART_OUT
// (formats by extension: .vtu .msh .inp .mesh .vtk ...).
#include <cstdio>
#include <exception>

#include "cad/cad_mesher.h"
#include "converters/registry.h"
#include "mesh/error.h"
#include "pipeline/mesher.h"

namespace {

// The unit box, one face id per side; the regions are left for the mesher
// to find (inside: region 1, outside: 0).
vd::Mesh unit_box() {
  vd::Mesh box;
  for (int i = 0; i < 8; ++i) box.points.push_back({double(i & 1), double((i >> 1) & 1), double((i >> 2) & 1)});
  const int sides[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  for (int face = 0; face < 6; ++face) {
    const int* q = sides[face];
    box.triangles.push_back({{q[0], q[1], q[2]}, face + 1});
    box.triangles.push_back({{q[0], q[2], q[3]}, face + 1});
  }
  return box;
}

void print_summary(const char* what, const vd::MeshResult& result) {
  std::printf("%s: %zu points, %zu tetrahedra, smallest dihedral angle %.2f deg\n", what, result.mesh.points.size(),
              result.mesh.tets.size(), result.report.quality.min_dihedral_deg);
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 4) {
    std::fprintf(stderr, "usage: %s BOX_OUT PART PART_OUT\n", argv[0]);
    return 2;
  }
  try {
    vd::MeshOptions options;
    options.size.uniform = 0.2;
    const vd::MeshResult box = vd::mesh_surface(unit_box(), options);
    print_summary("box", box);
    vd::io::write_mesh(box.mesh, argv[1]);

    vd::cad::CadMeshOptions cad_options;  // size chosen from the part
    const auto part = vd::cad::CadModel::read(argv[2], nullptr, cad_options.fuse);
    const vd::MeshResult meshed = vd::cad::mesh_cad(part, cad_options);
    print_summary("part", meshed);
    for (const vd::ReferenceMeasure& v : meshed.report.cad.volumes)
      std::printf("  %s: CAD volume %.6g, mesh %.6g\n", v.name.c_str(), v.reference, v.mesh);
    vd::io::write_mesh(meshed.mesh, argv[3]);
  } catch (const vd::InputError& e) {
    std::fprintf(stderr, "bad input: %s\n", e.what());
    return 3;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 1;
  }
  return 0;
}
