// VTU layouts other programs write and vdmesh does not: zlib-compressed
// inline arrays with UInt32 headers (meshio's default) and raw appended data
// (ParaView's default). Built here byte by byte.
#include <zlib.h>

#include <cstring>
#include <fstream>
#include <string>
#include <vector>

#include "converters/registry.h"
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
std::string compressed_inline(const std::string& raw) {
  uLongf size = compressBound(raw.size());
  std::string comp(size, '\0');
  EXPECT_EQ(compress2(reinterpret_cast<Bytef*>(comp.data()), &size, reinterpret_cast<const Bytef*>(raw.data()),
                      raw.size(), 6),
            Z_OK);
  comp.resize(size);
  const uint32_t header[4] = {1, uint32_t(raw.size()), uint32_t(raw.size()), uint32_t(comp.size())};
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

TEST(ConvertersVtu, ReadsZlibCompressedInlineArrays) {
  const Arrays a = arrays();
  auto arr = [&](const char* type, const char* name, int comps, const std::string& raw) {
    return array_tag(type, name, comps, "format=\"binary\">\n   " + compressed_inline(raw) + "\n</DataArray>\n");
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

}  // namespace
}  // namespace vd
