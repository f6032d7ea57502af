// Malformed input gives vd::InputError naming the file and the line (or the
// byte offset in binary data), never a crash, for every reader.
#include <sys/stat.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <thread>

#include "converters/registry.h"
#include "mesh/error.h"
#include "test_support.h"

namespace vd {
namespace {

void write_text(const std::string& path, const std::string& text) {
  std::ofstream(path, std::ios::binary) << text;
}

std::string read_bytes(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  std::stringstream s;
  s << f.rdbuf();
  return s.str();
}

// The message of the InputError reading `path` throws ("" when none).
std::string input_error(const std::string& path) {
  try {
    io::read_mesh(path);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

// Binary Medit elements vdmesh does not keep are refused, not skipped:
// libMeshb 7's third-order tetrahedra (keyword 96) read as no element at
// all. The file: the header, Dimension 3, one element of `code`, End.
TEST(ConvertersBadInput, MeshbElementsNotKeptAreRefused) {
  const std::pair<int32_t, const char*> cases[] = {
      {96, "1 third-order tetrahedra"}, {90, "1 third-order triangles"}, {86, "1 second-order prisms"}, {9, "1 prisms"}, {47, "1 polygons"},
      {200, "1 9-node prisms"}};
  for (const auto& [code, words] : cases) {
    std::string b;
    auto put32 = [&b](int32_t v) { b.append(reinterpret_cast<const char*>(&v), 4); };
    for (int32_t v : {1, 2, 3, 20, 3, code, 32, 1, 54, 0}) put32(v);
    const std::string path = test::temp_path("kept_" + std::to_string(code) + ".meshb");
    write_text(path, b);
    const std::string message = input_error(path);
    EXPECT_NE(message.find(path + ": byte 20: " + words + ": vdmesh reads triangles and tetrahedra only"),
              std::string::npos)
        << message;
  }
}

struct Snippet {
  const char* file;
  int line;  // where the error is; 0: a byte offset
  const char* text;
};

const Snippet kSnippets[] = {
    // OFF
    {"bad_number.off", 4, "OFF\n3 1 0\n0 0 0\n1 x 0\n0 1 0\n3 0 1 2\n"},
    {"bad_index.off", 6, "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 7\n"},
    {"nan.off", 3, "OFF\n3 1 0\n0 0 nan\n1 0 0\n0 1 0\n3 0 1 2\n"},
    {"inf.off", 4, "OFF\n3 1 0\n0 0 0\n1e999 0 0\n0 1 0\n3 0 1 2\n"},
    {"truncated.off", 5, "OFF\n3 1 0\n0 0 0\n1 0 0\n"},
    {"huge_count.off", 3, "OFF\n999999999999 1 0\n"},
    {"negative_count.off", 2, "OFF\n-3 1 0\n"},
    {"not_off.off", 1, "PLY\n3 1 0\n"},
    {"two_vertex_face.off", 6, "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n2 0 1\n"},
    // STL
    {"short_facet.stl", 6, "solid a\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nendloop\nendfacet\nendsolid\n"},
    {"bad_vertex.stl", 4, "solid a\n facet normal 0 0 1\n  outer loop\n   vertex 0 0 zz\n"},
    {"truncated.stl", 5, "solid a\n facet normal 0 0 1\n  outer loop\n   vertex 0 0 0\n"},
    {"nan.stl", 4, "solid a\n facet normal 0 0 1\n  outer loop\n   vertex 0 nan 0\n"},
    {"no_loop.stl", 3, "solid a\n facet normal 0 0 1\n  vertex 0 0 0\n"},
    // OBJ
    {"missing_vertex.obj", 3, "v 0 0 0\nv 1 0 0\nf 1 2 3\n"},
    {"short_vertex.obj", 2, "v 0 0 0\nv 1 0\nv 0 1 0\nf 1 2 3\n"},
    {"zero_index.obj", 4, "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n"},
    {"negative_too_far.obj", 4, "v 0 0 0\nv 1 0 0\nv 0 1 0\nf -1 -2 -4\n"},
    {"bad_face.obj", 4, "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 a 3\n"},
    {"two_vertex_face.obj", 4, "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2\n"},
    // Gmsh
    {"missing_node.msh", 11,
     "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n2\n1 0 0 0\n2 1 0 0\n$EndNodes\n$Elements\n1\n"
     "1 4 2 1 1 1 2 3 4\n$EndElements\n"},
    {"unknown_type.msh", 11,
     "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n2\n1 0 0 0\n2 1 0 0\n$EndNodes\n$Elements\n1\n"
     "1 99 2 1 1 1 2\n$EndElements\n"},
    {"short_nodes.msh", 7, "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n3\n1 0 0 0\n$EndNodes\n"},
    {"bad_version.msh", 2, "$MeshFormat\n3.0 0 8\n$EndMeshFormat\n"},
    {"no_header.msh", 1, "$Nodes\n0\n$EndNodes\n"},
    {"nan.msh", 6, "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n1\n1 0 nan 0\n$EndNodes\n"},
    {"duplicate_node.msh", 7, "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n2\n1 0 0 0\n1 1 0 0\n$EndNodes\n"},
    {"unclosed.msh", 4, "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Comments\nabc\n"},
    {"v41_missing_node.msh", 15,
     "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Nodes\n1 2 1 2\n3 1 0 2\n1\n2\n0 0 0\n1 0 0\n$EndNodes\n"
     "$Elements\n1 1 1 1\n3 1 4 1\n1 1 2 3 4\n$EndElements\n"},
    {"v41_bad_count.msh", 10,
     "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Nodes\n1 3 1 3\n3 1 0 2\n1\n2\n0 0 0\n1 0 0\n$EndNodes\n"},
    {"v41_unknown_type.msh", 14,
     "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Nodes\n1 2 1 2\n3 1 0 2\n1\n2\n0 0 0\n1 0 0\n$EndNodes\n"
     "$Elements\n1 1 1 1\n3 1 77 1\n1 1 2\n$EndElements\n"},
    // VTK legacy
    {"missing_point.vtk", 9,
     "# vtk DataFile Version 3.0\nx\nASCII\nDATASET UNSTRUCTURED_GRID\nPOINTS 2 double\n0 0 0\n1 1 1\n"
     "CELLS 1 5\n4 0 1 2 3\nCELL_TYPES 1\n10\n"},
    {"bad_point.vtk", 7,
     "# vtk DataFile Version 3.0\nx\nASCII\nDATASET UNSTRUCTURED_GRID\nPOINTS 2 double\n0 0 0\n1 y 1\n"},
    {"not_vtk.vtk", 1, "hello\n"},
    {"polydata.vtk", 4, "# vtk DataFile Version 3.0\nx\nASCII\nDATASET STRUCTURED_POINTS\n"},
    {"polygon_missing_point.vtk", 10,
     "# vtk DataFile Version 3.0\nx\nASCII\nDATASET POLYDATA\nPOINTS 3 float\n0 0 0\n1 0 0\n0 1 0\n"
     "POLYGONS 1 5\n4 0 1 2 3\n"},
    {"polygons_first.vtk", 5, "# vtk DataFile Version 3.0\nx\nASCII\nDATASET POLYDATA\nPOLYGONS 1 4\n3 0 1 2\n"},
    {"polygon_of_two.vtk", 0,
     "# vtk DataFile Version 3.0\nx\nASCII\nDATASET POLYDATA\nPOINTS 3 float\n0 0 0\n1 0 0\n0 1 0\n"
     "POLYGONS 1 3\n2 0 1\n"},
    {"polydata_points_only.vtk", 0,
     "# vtk DataFile Version 3.0\nx\nASCII\nDATASET POLYDATA\nPOINTS 3 float\n0 0 0\n1 0 0\n0 1 0\n"},
    // PLY
    {"not_ply.ply", 1, "plywood\n"},
    {"ply_no_end.ply", 0, "ply\nformat ascii 1.0\nelement vertex 1\n"},
    {"ply_bad_format.ply", 2, "ply\nformat binary_middle_endian 1.0\nend_header\n"},
    {"ply_bad_type.ply", 4, "ply\nformat ascii 1.0\nelement vertex 1\nproperty quad x\nend_header\n"},
    {"ply_no_z.ply", 0,
     "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nend_header\n0 0\n"},
    {"ply_missing_vertex.ply", 13,
     "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
     "element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 3\n"},
    {"ply_bad_number.ply", 10,
     "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
     "element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 zero\n"},
    {"ply_short.ply", 0,
     "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
     "property float z\nend_header\nabc"},
    {"ply_two_vertices.ply", 13,
     "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
     "element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n2 0 1\n"},
    {"ply_strip_missing_vertex.ply", 13,
     "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
     "element tristrips 1\nproperty list int int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n4 0 1 2 3\n"},
    {"ply_strip_minus_two.ply", 13,
     "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
     "element tristrips 1\nproperty list int int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n4 0 1 2 -2\n"},
    {"ply_strips_first.ply", 10,
     "ply\nformat ascii 1.0\nelement tristrips 1\nproperty list int int vertex_indices\nelement vertex 3\n"
     "property float x\nproperty float y\nproperty float z\nend_header\n3 0 1 2\n0 0 0\n1 0 0\n0 1 0\n"},
    {"polydata_cells_after_data.vtk", 12,
     "# vtk DataFile Version 3.0\nx\nASCII\nDATASET POLYDATA\nPOINTS 3 float\n0 0 0\n1 0 0\n0 1 0\n"
     "POLYGONS 1 4\n3 0 1 2\nCELL_DATA 1\nPOLYGONS 1 4\n3 0 1 2\n"},
    {"short_types.vtk", 14,
     "# vtk DataFile Version 3.0\nx\nASCII\nDATASET UNSTRUCTURED_GRID\nPOINTS 4 double\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n"
     "CELLS 1 5\n4 0 1 2 3\nCELL_TYPES 2\n10\n"},
    // VTU
    {"bad_value.vtu", 5,
     "<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\">\n<UnstructuredGrid>\n"
     "<Piece NumberOfPoints=\"1\" NumberOfCells=\"0\">\n<Points><DataArray type=\"Float64\" "
     "NumberOfComponents=\"3\" format=\"ascii\">0 0 x</DataArray></Points>\n</Piece></UnstructuredGrid></VTKFile>\n"},
    {"missing_point.vtu", 7,
     "<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\">\n<UnstructuredGrid>\n"
     "<Piece NumberOfPoints=\"1\" NumberOfCells=\"1\">\n<Points><DataArray type=\"Float64\" "
     "NumberOfComponents=\"3\" format=\"ascii\">0 0 0</DataArray></Points>\n<Cells>\n"
     "<DataArray type=\"Int64\" Name=\"connectivity\" format=\"ascii\">0 1 2 3</DataArray>\n"
     "<DataArray type=\"Int64\" Name=\"offsets\" format=\"ascii\">4</DataArray>\n"
     "<DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">10</DataArray>\n"
     "</Cells></Piece></UnstructuredGrid></VTKFile>\n"},
    {"bad_base64.vtu", 4,
     "<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" header_type=\"UInt64\">\n<UnstructuredGrid>\n"
     "<Piece NumberOfPoints=\"1\" NumberOfCells=\"0\"><Points><DataArray type=\"Float64\" "
     "NumberOfComponents=\"3\" format=\"binary\">!!!!</DataArray></Points>\n</Piece></UnstructuredGrid></VTKFile>\n"},
    {"short_binary.vtu", 4,
     "<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" header_type=\"UInt64\">\n<UnstructuredGrid>\n"
     "<Piece NumberOfPoints=\"1\" NumberOfCells=\"0\"><Points><DataArray type=\"Float64\" "
     "NumberOfComponents=\"3\" format=\"binary\">/////////////w==</DataArray></Points>\n</Piece></UnstructuredGrid></VTKFile>\n"},
    {"unclosed.vtu", 2, "<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" \n"},
    // Medit
    {"missing_vertex.mesh", 8, "MeshVersionFormatted 2\nDimension 3\nVertices\n1\n0 0 0 0\nTetrahedra\n1\n1 2 3 4 1\nEnd\n"},
    {"dimension2.mesh", 2, "MeshVersionFormatted 2\nDimension 2\n"},
    {"unknown_section.mesh", 3, "MeshVersionFormatted 2\nDimension 3\nBananas 3\n"},
    {"bad_coordinate.mesh", 5, "MeshVersionFormatted 2\nDimension 3\nVertices\n1\n0 q 0 0\nEnd\n"},
    // Elements vdmesh would lose (a prism read as nothing, exit 0, before).
    {"prism.msh", 15,
     "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n6\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n5 1 0 1\n6 0 1 1\n"
     "$EndNodes\n$Elements\n1\n1 6 2 1 1 1 2 3 4 5 6\n$EndElements\n"},
    {"hexahedra.mesh", 14,
     "MeshVersionFormatted 2\nDimension 3\nVertices\n8\n0 0 0 0\n1 0 0 0\n1 1 0 0\n0 1 0 0\n0 0 1 0\n1 0 1 0\n"
     "1 1 1 0\n0 1 1 0\nHexahedra\n1\n1 2 3 4 5 6 7 8 1\nEnd\n"},
    {"wedge.vtk", 0,
     "# vtk DataFile Version 4.2\nw\nASCII\nDATASET UNSTRUCTURED_GRID\nPOINTS 6 double\n0 0 0 1 0 0 0 1 0 0 0 1 1 0 1 0 1 1\n"
     "CELLS 1 7\n6 0 1 2 3 4 5\nCELL_TYPES 1\n13\n"},
    // TetGen
    {"gap.node", 3, "2 3 0 0\n1 0 0 0\n3 1 1 1\n"},
    {"dim2.node", 1, "2 2 0 0\n1 0 0\n2 1 1\n"},
    {"bad_polygon.poly", 8, "4 3 0 0\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n1 0\n1 0 1\n3 1 2 9\n"},
    {"bad_facet.smesh", 7, "4 3 0 0\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n1 0\n3 1 2 x\n"},
    {"truncated.smesh", 8, "4 3 0 0\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n2 0\n3 1 2 3\n"},
    // Abaqus
    {"missing_node.inp", 4, "*NODE\n1, 0, 0, 0\n*ELEMENT, TYPE=C3D4, ELSET=Region1\n1, 1, 2, 3, 4\n"},
    {"bad_coordinate.inp", 3, "** comment\n*NODE\n1, 0, zero, 0\n"},
    {"short_element.inp", 7,
     "*NODE\n1, 0, 0, 0\n2, 1, 0, 0\n3, 0, 1, 0\n4, 0, 0, 1\n*ELEMENT, TYPE=C3D4\n1, 1, 2, 3\n"},
    {"bad_face.inp", 9,
     "*NODE\n1, 0, 0, 0\n2, 1, 0, 0\n3, 0, 1, 0\n4, 0, 0, 1\n*ELEMENT, TYPE=C3D4\n1, 1, 2, 3, 4\n*SURFACE, NAME=A\n"
     "1, S7\n"},
    {"data_outside.inp", 1, "1, 2, 3\n"},
    // Abaqus/CAE assemblies vdmesh cannot place (a translation was dropped, exit 0, before).
    {"moved_instance.inp", 7,
     "*PART, NAME=P\n*NODE\n1, 0, 0, 0\n*END PART\n*ASSEMBLY, NAME=A\n*INSTANCE, NAME=I, PART=P\n5., 0., 0.\n"
     "*END INSTANCE\n"},
    {"two_parts.inp", 3, "*PART, NAME=A\n*END PART\n*PART, NAME=B\n*END PART\n"},
    {"hexahedra.inp", 3, "*NODE\n1, 0, 0, 0\n*ELEMENT, TYPE=C3D8R, ELSET=Block\n1, 1, 1, 1, 1, 1, 1, 1, 1\n"},
    {"duplicate_element.inp", 8,
     "*NODE\n1, 0, 0, 0\n2, 1, 0, 0\n3, 0, 1, 0\n4, 0, 0, 1\n*ELEMENT, TYPE=C3D4\n1, 1, 2, 3, 4\n1, 1, 2, 4, 3\n"},
    // *INCLUDE: a file that is not there, a folder, a deck that includes itself.
    {"include_missing.inp", 2, "*NODE\n*INCLUDE, INPUT=no-such-nodes.inp\n"},
    {"include_folder.inp", 1, "*INCLUDE, INPUT=.\n"},
    {"include_self.inp", 2, "** again\n*INCLUDE, INPUT=include_self.inp\n"},
    {"mixed_order.inp", 9,
     "*NODE\n1, 0, 0, 0\n2, 1, 0, 0\n3, 0, 1, 0\n4, 0, 0, 1\n*ELEMENT, TYPE=C3D4\n1, 1, 2, 3, 4\n"
     "*ELEMENT, TYPE=C3D10\n2, 1, 2, 3, 4, 1, 2, 3, 4, 1, 2\n"},
};

TEST(ConvertersBadInput, EverySnippetNamesFileAndLine) {
  for (const Snippet& s : kSnippets) {
    SCOPED_TRACE(s.file);
    const std::string path = test::temp_path(s.file);
    write_text(path, s.text);
    const std::string msg = input_error(path);
    ASSERT_FALSE(msg.empty()) << "no InputError";
    EXPECT_EQ(msg.rfind(path + ":", 0), 0u) << msg;
    if (s.line > 0) EXPECT_EQ(msg.rfind(path + ":" + std::to_string(s.line) + ": ", 0), 0u) << msg;
  }
}

TEST(ConvertersBadInput, UnknownExtensionIsUsageError) {
  EXPECT_THROW(io::read_mesh("mesh.xyz"), UsageError);
  EXPECT_THROW(io::format_for("mesh.xyz.gz"), UsageError);
  EXPECT_THROW(io::format_for("mesh", "nosuchformat"), UsageError);
  EXPECT_EQ(io::format_for("A.MSH.gz").name, "gmsh");
  EXPECT_THROW(io::format_for("dir.v2/mesh"), UsageError);
}

TEST(ConvertersBadInput, MissingFileIsInputError) {
  const std::string msg = input_error(test::temp_path("does-not-exist.msh"));
  EXPECT_NE(msg.find("does-not-exist.msh"), std::string::npos) << msg;
}

// A small valid volume mesh (two tetrahedra and their boundary).
Mesh two_tets() {
  Mesh m;
  m.points = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {1, 1, 1}};
  m.tets = {{{0, 1, 2, 3}, 1}, {{1, 2, 3, 4}, 2}};
  m.triangles = {{{0, 2, 1}, 1, 0, 1}, {{1, 2, 3}, 2, 2, 1}, {{1, 4, 2}, 3, 0, 2}};
  return m;
}

// The writers trust the arrays; write_mesh checks them first (a node past
// the points, or a short mid-edge list, was read past and written out).
TEST(ConvertersBadInput, InconsistentArraysAreNotWritten) {
  for (const char* file : {"w.msh", "w.vtu", "w.inp", "w.meshb"}) {
    Mesh m = two_tets();
    m.tets[1].v[3] = 1000000;
    const std::string path = test::temp_path(file);
    EXPECT_THROW(io::write_mesh(m, path), InputError) << file;
    m = two_tets();
    m.tet_mid.resize(1);
    EXPECT_THROW(io::write_mesh(m, path), InputError) << file;
    EXPECT_FALSE(std::filesystem::exists(path)) << file;
  }
}

// Where a written file goes (io::write_target): a symlink's target, a FIFO in
// place, a replaced file's permissions kept. A link became a plain file, a
// 0600 file 0644, and a FIFO a plain file its reader never saw (2026-11-30).
TEST(ConvertersBadInput, WritingKeepsLinksAndPermissions) {
  namespace fs = std::filesystem;
  const Mesh m = two_tets();
  const fs::path real = test::temp_path("real.msh"), link = test::temp_path("link.msh");
  fs::remove(real);
  fs::remove(link);
  write_text(real.string(), "old");
  fs::permissions(real, fs::perms::owner_read | fs::perms::owner_write);
  fs::create_symlink(real, link);
  io::write_mesh(m, link.string());
  EXPECT_TRUE(fs::is_symlink(link));
  EXPECT_EQ(io::read_mesh(real.string()).tets.size(), 2u);
  EXPECT_EQ(fs::status(real).permissions() & fs::perms::all, fs::perms::owner_read | fs::perms::owner_write);
  // A FIFO is written into, not replaced: its reader gets the file.
  const fs::path fifo = test::temp_path("fifo.off");
  fs::remove(fifo);
  ASSERT_EQ(mkfifo(fifo.c_str(), 0600), 0);
  std::string got;
  std::thread reader([&] { got = read_bytes(fifo.string()); });
  io::write_mesh(m, fifo.string());
  reader.join();
  EXPECT_TRUE(fs::is_fifo(fifo));
  EXPECT_EQ(got.rfind("OFF", 0), 0u) << got.substr(0, 20);
  fs::remove(fifo);
}

// Every prefix length of a valid file (sampled) either reads or throws
// InputError; half the file always fails (an Abaqus deck: cut inside an
// element line).
TEST(ConvertersBadInput, TruncatedFilesFailCleanly) {
  const Mesh m = two_tets();
  struct Case {
    const char* file;
    bool binary;
    int version;
  };
  const Case cases[] = {{"t.msh", false, 22}, {"t.msh", true, 22},  {"t.msh", false, 41}, {"t.msh", true, 41},
                        {"t.vtk", false, 41}, {"t.vtk", true, 41},  {"t.vtu", false, 41}, {"t.vtu", true, 41},
                        {"t.inp", false, 41}, {"t.mesh", false, 41}, {"t.stl", true, 41}, {"t.stl", false, 41},
                        {"t.off", false, 41}, {"t.obj", false, 41},  {"t.smesh", false, 41}};
  for (const Case& c : cases) {
    SCOPED_TRACE(std::string(c.file) + (c.binary ? " binary" : " ascii") + std::to_string(c.version));
    const std::string path = test::temp_path(std::string(c.binary ? "b" : "a") + std::to_string(c.version) + c.file);
    io::write_mesh(m, path, {c.binary, c.version});
    const std::string full = read_bytes(path);
    ASSERT_NO_THROW(io::read_mesh(path));
    const std::string cut = test::temp_path(std::string("cut.") + (c.binary ? "b" : "a") +
                                            std::to_string(c.version) + c.file);
    const size_t step = std::max<size_t>(1, full.size() / 41);
    for (size_t n = 0; n < full.size(); n += step) {
      write_text(cut, full.substr(0, n));
      try {
        io::read_mesh(cut);
      } catch (const InputError& e) {
        EXPECT_EQ(std::string(e.what()).rfind(cut, 0), 0u) << e.what();
      }
    }
    // An Abaqus deck has no counts and no end: cut after a line of its
    // trailing sets it is a valid deck (half of this one ends in a node set
    // since the writer gives each region one). What must fail there is an
    // element line cut short.
    // A .smesh facet's marker may be left out and its region and hole lists
    // are optional: cut inside its first facet's vertex list.
    size_t half = full.size() / 2;
    if (std::string(c.file) == "t.inp") half = full.find('\n', full.find("*ELEMENT")) + 4;
    if (std::string(c.file) == "t.smesh") {
      // A comment, the node header, 5 nodes and the facet header come first.
      size_t first_facet = 0;
      for (int line = 0; line < 8; ++line) first_facet = full.find('\n', first_facet) + 1;
      half = first_facet + 4;
    }
    write_text(cut, full.substr(0, half));
    EXPECT_FALSE(input_error(cut).empty()) << "half a file read without error";
  }
}

// Flipping bytes of binary files must not crash (ASan/UBSan builds check it).
TEST(ConvertersBadInput, CorruptedBinaryFilesFailCleanly) {
  const Mesh m = two_tets();
  for (const char* file : {"c.msh", "c.vtk", "c.vtu", "c.stl"})
    for (int version : {22, 41}) {
      SCOPED_TRACE(std::string(file) + std::to_string(version));
      const std::string path = test::temp_path(std::to_string(version) + file);
      io::write_mesh(m, path, {true, version});
      const std::string full = read_bytes(path);
      const std::string bad = test::temp_path(std::string("bad") + std::to_string(version) + file);
      for (size_t i = 0; i < full.size(); i += 7) {
        std::string b = full;
        b[i] = static_cast<char>(b[i] ^ 0xA5);
        write_text(bad, b);
        try {
          io::read_mesh(bad);
        } catch (const InputError&) {
        }
      }
    }
}

TEST(ConvertersBadInput, BinaryErrorsNameTheByte) {
  const std::string path = test::temp_path("short.stl");
  std::string bytes(80, ' ');
  const uint32_t n = 1000;
  bytes.append(reinterpret_cast<const char*>(&n), 4);
  bytes.append(60, '\0');
  write_text(path, bytes);
  const std::string msg = input_error(path);
  EXPECT_EQ(msg.rfind(path + ": byte ", 0), 0u) << msg;
}

}  // namespace
}  // namespace vd
