// VTU layouts other programs write and vdmesh does not: zlib-compressed
// inline arrays with UInt32 headers (meshio's default) and raw appended data
// (ParaView's default), and what VTK's own writers add to ASCII and legacy
// files. Built here byte by byte.
#include <zlib.h>

#include <algorithm>
#include <cstring>
#include <fstream>
#include <string>
#include <vector>

#include "converters/registry.h"
#include "mesh/error.h"
#include "test_support.h"

namespace vd {
namespace {

std::string bytes_of(const void* p, size_t n) { return std::string(static_cast<const char*>(p), n); }

std::string base64(const std::string& in) {
  static const char* k = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  size_t i = 0;
  for (; i + 2 < in.size(); i += 3) {
    const uint32_t v = (uint8_t(in[i]) << 16) | (uint8_t(in[i + 1]) << 8) | uint8_t(in[i + 2]);
    for (int s : {18, 12, 6, 0}) out += k[(v >> s) & 63];
  }
  if (i < in.size()) {
    const uint32_t v = (uint8_t(in[i]) << 16) | (i + 1 < in.size() ? uint8_t(in[i + 1]) << 8 : 0);
    out += k[(v >> 18) & 63];
    out += k[(v >> 12) & 63];
    out += i + 1 < in.size() ? k[(v >> 6) & 63] : '=';
    out += '=';
  }
  return out;
}

// One zlib block with a UInt32 header, header and data encoded separately.
// `block_size`: the header's, 0 for the array's size.
std::string compressed_inline(const std::string& raw, uint32_t block_size = 0) {
  uLongf size = compressBound(raw.size());
  std::string comp(size, '\0');
  EXPECT_EQ(compress2(reinterpret_cast<Bytef*>(comp.data()), &size, reinterpret_cast<const Bytef*>(raw.data()),
                      raw.size(), 6),
            Z_OK);
  comp.resize(size);
  const uint32_t header[4] = {1, block_size ? block_size : uint32_t(raw.size()), uint32_t(raw.size()),
                              uint32_t(comp.size())};
  return base64(bytes_of(header, sizeof header)) + base64(comp);
}

struct Arrays {
  std::string points, conn, offsets, types, region;
};

// A positive tetrahedron and a triangle, region 5 / face 3.
Arrays arrays() {
  const double p[12] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0.25, 0.5, 1.5};
  const int64_t conn[7] = {0, 1, 2, 3, 0, 2, 1};
  const int64_t offsets[2] = {4, 7};
  const uint8_t types[2] = {10, 5};
  const int32_t region[2] = {5, 3};
  return {bytes_of(p, sizeof p), bytes_of(conn, sizeof conn), bytes_of(offsets, sizeof offsets),
          bytes_of(types, sizeof types), bytes_of(region, sizeof region)};
}

void expect_tet(const Mesh& m) {
  ASSERT_EQ(m.points.size(), 4u);
  EXPECT_EQ(m.points[3].x, 0.25);
  EXPECT_EQ(m.points[3].z, 1.5);
  ASSERT_EQ(m.tets.size(), 1u);
  EXPECT_EQ(m.tets[0].v, (std::array<int, 4>{0, 1, 2, 3}));
  EXPECT_EQ(m.tets[0].region, 5);
  ASSERT_EQ(m.triangles.size(), 1u);
  EXPECT_EQ(m.triangles[0].v, (std::array<int, 3>{0, 2, 1}));
  // The triangle's normal (-z) points out of the tetrahedron: back = 5.
  EXPECT_EQ(m.triangles[0].back, 5);
  EXPECT_EQ(m.triangles[0].front, 0);
}

std::string array_tag(const char* type, const char* name, int comps, const std::string& rest) {
  return std::string("<DataArray type=\"") + type + "\" Name=\"" + name + "\" NumberOfComponents=\"" +
         std::to_string(comps) + "\" " + rest;
}

void read_zlib_compressed(uint32_t block_size) {
  const Arrays a = arrays();
  auto arr = [&](const char* type, const char* name, int comps, const std::string& raw) {
    return array_tag(type, name, comps,
                     "format=\"binary\">\n   " + compressed_inline(raw, block_size) + "\n</DataArray>\n");
  };
  const std::string xml =
      "<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"0.1\" byte_order=\"LittleEndian\" "
      "compressor=\"vtkZLibDataCompressor\">\n<!-- a comment -->\n<UnstructuredGrid>\n"
      "<Piece NumberOfPoints=\"4\" NumberOfCells=\"2\">\n<Points>\n" +
      arr("Float64", "Points", 3, a.points) + "</Points>\n<Cells>\n" + arr("Int64", "connectivity", 1, a.conn) +
      arr("Int64", "offsets", 1, a.offsets) + arr("UInt8", "types", 1, a.types) + "</Cells>\n<CellData>\n" +
      arr("Int32", "medit:ref", 1, a.region) + "</CellData>\n</Piece>\n</UnstructuredGrid>\n</VTKFile>\n";
  const std::string path = test::temp_path("zlib.vtu");
  std::ofstream(path, std::ios::binary) << xml;
  expect_tet(io::read_mesh(path));
}

TEST(ConvertersVtu, ReadsZlibCompressedInlineArrays) { read_zlib_compressed(0); }

// VTK and meshio declare their block size (32768) in the header whatever
// the array's size; the last block's size says what the one block holds.
// Every such file of under 32 KiB an array was refused ("compressed block
// sizes do not match the array") until 2026-11-29.
TEST(ConvertersVtu, ReadsOneBlockDeclaredLargerThanItsArray) { read_zlib_compressed(32768); }

// vtkXMLUnstructuredGridWriter's ASCII files put an <InformationKey> (the
// points' norm range) after the numbers, inside the DataArray.
TEST(ConvertersVtu, AsciiArraysEndAtTheirFirstChildElement) {
  const std::string xml =
      "<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"0.1\" byte_order=\"LittleEndian\">\n"
      "<UnstructuredGrid>\n<Piece NumberOfPoints=\"4\" NumberOfCells=\"2\">\n<CellData>\n"
      "<DataArray type=\"Int32\" Name=\"region\" format=\"ascii\">\n 5 3\n</DataArray>\n</CellData>\n"
      "<Points>\n<DataArray type=\"Float32\" Name=\"Points\" NumberOfComponents=\"3\" format=\"ascii\">\n"
      "  0 0 0 1 0 0\n  0 1 0 0.25 0.5 1.5\n"
      "  <InformationKey name=\"L2_NORM_RANGE\" location=\"vtkDataArray\" length=\"2\">\n"
      "    <Value index=\"0\">\n      0\n    </Value>\n    <Value index=\"1\">\n      1.6\n    </Value>\n"
      "  </InformationKey>\n</DataArray>\n</Points>\n<Cells>\n"
      "<DataArray type=\"Int64\" Name=\"connectivity\" format=\"ascii\">\n 0 1 2 3 0 2 1\n</DataArray>\n"
      "<DataArray type=\"Int64\" Name=\"offsets\" format=\"ascii\">\n 4 7\n</DataArray>\n"
      "<DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">\n 10 5\n</DataArray>\n"
      "</Cells>\n</Piece>\n</UnstructuredGrid>\n</VTKFile>\n";
  const std::string path = test::temp_path("infokey.vtu");
  std::ofstream(path, std::ios::binary) << xml;
  expect_tet(io::read_mesh(path));
}

// Legacy files of VTK 8 and later follow each FIELD array with METADATA;
// after the first array the reader wanted the second's name and found
// "INFORMATION".
TEST(ConvertersVtu, LegacyFieldArraysWithMetadata) {
  const std::string vtk =
      "# vtk DataFile Version 4.2\nvtk output\nASCII\nDATASET UNSTRUCTURED_GRID\nPOINTS 4 double\n"
      "0 0 0 1 0 0 0 1 0\n0.25 0.5 1.5\nMETADATA\nINFORMATION 0\n\n"
      "CELLS 2 9\n4 0 1 2 3\n3 0 2 1\nCELL_TYPES 2\n10\n5\nCELL_DATA 2\nFIELD FieldData 2\n"
      "other 1 2 int\n7 7\nMETADATA\nINFORMATION 0\n\nregion 1 2 int\n5 3\nMETADATA\nINFORMATION 0\n\n";
  const std::string path = test::temp_path("metadata.vtk");
  std::ofstream(path, std::ios::binary) << vtk;
  expect_tet(io::read_mesh(path));
}

TEST(ConvertersVtu, ReadsRawAppendedData) {
  const Arrays a = arrays();
  std::string blob;
  auto arr = [&](const char* type, const char* name, int comps, const std::string& raw) {
    const std::string tag =
        array_tag(type, name, comps, "format=\"appended\" offset=\"" + std::to_string(blob.size()) + "\"/>\n");
    const uint64_t n = raw.size();
    blob += bytes_of(&n, 8) + raw;
    return tag;
  };
  std::string xml =
      "<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\" "
      "header_type=\"UInt64\">\n<UnstructuredGrid>\n<Piece NumberOfPoints=\"4\" NumberOfCells=\"2\">\n<Points>\n";
  xml += arr("Float64", "Points", 3, a.points) + "</Points>\n<Cells>\n";
  xml += arr("Int64", "connectivity", 1, a.conn);
  xml += arr("Int64", "offsets", 1, a.offsets);
  xml += arr("UInt8", "types", 1, a.types);
  xml += "</Cells>\n<CellData>\n" + arr("Int32", "region", 1, a.region) + "</CellData>\n</Piece>\n</UnstructuredGrid>\n";
  xml += "<AppendedData encoding=\"raw\">\n   _" + blob + "\n</AppendedData>\n</VTKFile>\n";
  const std::string path = test::temp_path("appended.vtu");
  std::ofstream(path, std::ios::binary) << xml;
  const Mesh m = io::read_mesh(path);
  expect_tet(m);
}

// VTK's own uncompressed binary: the header and the data base64-encoded
// apart (the header's padding sits between them). A poly-vertex and a
// poly-line (their sizes only in the offsets) come first and are skipped;
// their nodes still count in the connectivity. A Float32 region array is
// converted.
TEST(ConvertersVtu, ReadsSeparatelyEncodedHeadersAndSkipsLines) {
  const double p[15] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0.25, 0.5, 1.5, 2, 2, 2};
  // poly-vertex (0 1 4), poly-line (2 1 4 3), tetrahedron (0 1 2 3), triangle (0 2 1)
  const int64_t c[14] = {0, 1, 4, 2, 1, 4, 3, 0, 1, 2, 3, 0, 2, 1};
  const int64_t offsets[4] = {3, 7, 11, 14};
  const uint8_t types[4] = {2, 4, 10, 5};
  const float region[4] = {8, 9, 5, 3};
  auto arr = [&](const char* type, const char* name, int comps, const std::string& raw) {
    const uint32_t n = uint32_t(raw.size());
    return array_tag(type, name, comps,
                     "format=\"binary\">\n  " + base64(bytes_of(&n, 4)) + base64(raw) + "\n</DataArray>\n");
  };
  const std::string xml =
      "<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"0.1\" byte_order=\"LittleEndian\">\n"
      "<UnstructuredGrid>\n<Piece NumberOfPoints=\"5\" NumberOfCells=\"4\">\n<Points>\n" +
      arr("Float64", "Points", 3, bytes_of(p, sizeof p)) + "</Points>\n<Cells>\n" +
      arr("Int64", "connectivity", 1, bytes_of(c, sizeof c)) + arr("Int64", "offsets", 1, bytes_of(offsets, sizeof offsets)) +
      arr("UInt8", "types", 1, bytes_of(types, sizeof types)) + "</Cells>\n<CellData>\n" +
      arr("Float32", "CellEntityIds", 1, bytes_of(region, sizeof region)) +
      "</CellData>\n</Piece>\n</UnstructuredGrid>\n</VTKFile>\n";
  const std::string path = test::temp_path("separate.vtu");
  std::ofstream(path, std::ios::binary) << xml;
  const Mesh m = io::read_mesh(path);
  ASSERT_EQ(m.points.size(), 5u);
  EXPECT_EQ(m.points[4].z, 2.0);
  ASSERT_EQ(m.tets.size(), 1u);
  EXPECT_EQ(m.tets[0].v, (std::array<int, 4>{0, 1, 2, 3}));
  EXPECT_EQ(m.tets[0].region, 5);
  ASSERT_EQ(m.triangles.size(), 1u);
  EXPECT_EQ(m.triangles[0].v, (std::array<int, 3>{0, 2, 1}));
  EXPECT_EQ(m.triangles[0].face, 3);
  EXPECT_EQ(m.triangles[0].back, 5);
}

// A fixed-size cell whose offsets give it another size names the cell.
TEST(ConvertersVtu, OffsetsThatContradictATypeAreRefused) {
  const std::string xml =
      "<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\">\n<UnstructuredGrid>\n"
      "<Piece NumberOfPoints=\"4\" NumberOfCells=\"1\">\n<Points><DataArray type=\"Float64\" "
      "NumberOfComponents=\"3\" format=\"ascii\">0 0 0 1 0 0 0 1 0 0 0 1</DataArray></Points>\n<Cells>\n"
      "<DataArray type=\"Int64\" Name=\"connectivity\" format=\"ascii\">0 1 2</DataArray>\n"
      "<DataArray type=\"Int64\" Name=\"offsets\" format=\"ascii\">3</DataArray>\n"
      "<DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">10</DataArray>\n"
      "</Cells></Piece></UnstructuredGrid></VTKFile>\n";
  const std::string path = test::temp_path("contradicting.vtu");
  std::ofstream(path, std::ios::binary) << xml;
  try {
    io::read_mesh(path);
    FAIL() << "read a tetrahedron with 3 nodes";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(path + ":8: cell 0 of type 10 has offsets for 3 nodes, not 4"), std::string::npos)
        << e.what();
  }
}

// Legacy VTK 5.1 (OFFSETS / CONNECTIVITY), binary: a poly-line skipped, cell
// data given twice, "region" after "gmsh:physical": vdmesh's own name wins
// whatever the order.
TEST(ConvertersVtu, LegacyOffsetsLayoutAndTagPriority) {
  auto be = [](auto v) {
    std::string b = bytes_of(&v, sizeof v);
    std::reverse(b.begin(), b.end());
    return b;
  };
  std::string f = "# vtk DataFile Version 5.1\nx\nBINARY\nDATASET UNSTRUCTURED_GRID\nPOINTS 5 double\n";
  for (double v : {0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.25, 0.5, 1.5, 2.0, 2.0, 2.0}) f += be(v);
  f += "\nCELLS 4 10\nOFFSETS vtktypeint64\n";
  for (int64_t v : {0, 3, 7, 10}) f += be(v);
  f += "\nCONNECTIVITY vtktypeint64\n";
  for (int64_t v : {0, 1, 4, 0, 1, 2, 3, 0, 2, 1}) f += be(v);
  f += "\nCELL_TYPES 3\n";
  for (int32_t v : {4, 10, 5}) f += be(v);
  f += "\nCELL_DATA 3\nSCALARS gmsh:physical int 1\nLOOKUP_TABLE default\n";
  for (int32_t v : {1, 2, 7}) f += be(v);
  f += "\nSCALARS region int 1\nLOOKUP_TABLE default\n";
  for (int32_t v : {-1, 6, 0}) f += be(v);
  f += "\n";
  const std::string path = test::temp_path("offsets51.vtk");
  std::ofstream(path, std::ios::binary) << f;
  const Mesh m = io::read_mesh(path);
  ASSERT_EQ(m.tets.size(), 1u);
  EXPECT_EQ(m.tets[0].v, (std::array<int, 4>{0, 1, 2, 3}));
  EXPECT_EQ(m.tets[0].region, 6);  // "region", not gmsh:physical's 2
  ASSERT_EQ(m.triangles.size(), 1u);
  EXPECT_EQ(m.triangles[0].face, 7);  // no "face" array: the tags give it
  EXPECT_EQ(m.triangles[0].back, 6);
}

}  // namespace
}  // namespace vd
