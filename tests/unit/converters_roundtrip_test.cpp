// Round trips through every format: read(write(m)) keeps what the format can
// carry. Volume meshes are a unit cube split into 6 positive tetrahedra in
// two regions, with its 12 boundary triangles (face id per cube side) and
// the interface triangles between the regions (face 7).
#include <algorithm>
#include <array>
#include <chrono>
#include <atomic>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <sstream>
#include <set>
#include <thread>
#include <tuple>

#include "converters/formats/polygon_triangulation.h"
#include "converters/registry.h"
#include "geometry/predicates.h"
#include "mesh/error.h"
#include "mesh/parallel.h"
#include "mesh/second_order.h"
#include "mesh/shapes.h"
#include "test_support.h"

namespace vd {
namespace {

Vec3 corner(int i) { return {double(i & 1), double((i >> 1) & 1), double((i >> 2) & 1)}; }

double det(const Mesh& m, const std::array<int, 4>& t) {
  const Vec3 a = m.points[t[0]];
  return dot(cross(m.points[t[1]] - a, m.points[t[2]] - a), m.points[t[3]] - a);
}

// Scaled and shifted so coordinates have many significant digits.
Mesh cube_tets() {
  Mesh m;
  for (int i = 0; i < 8; ++i) {
    const Vec3 c = corner(i);
    m.points.push_back({0.1 + c.x * 1.7, -2.3 + c.y * 0.3, 1e-3 + c.z / 3.0});
  }
  const int axes[6][3] = {{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}};
  for (const auto& a : axes) {
    const int v1 = 1 << a[0], v2 = v1 | (1 << a[1]);
    Tetrahedron t;
    t.v = {0, v1, v2, 7};
    if (det(m, t.v) < 0) std::swap(t.v[1], t.v[2]);
    const Vec3 c = corner(v1) + corner(v2);
    t.region = c.x >= c.y ? 1 : 2;
    m.tets.push_back(t);
  }
  // Faces seen once are the boundary, faces of two regions the interface.
  std::map<std::array<int, 3>, std::vector<std::pair<std::array<int, 3>, int>>> faces;
  static const int inward[4][3] = {{1, 3, 2}, {0, 2, 3}, {0, 3, 1}, {0, 1, 2}};
  for (const Tetrahedron& t : m.tets)
    for (const auto& f : inward) {
      std::array<int, 3> tri{t.v[f[0]], t.v[f[2]], t.v[f[1]]};  // outward
      std::array<int, 3> key = tri;
      std::sort(key.begin(), key.end());
      faces[key].push_back({tri, t.region});
    }
  for (const auto& [key, sides] : faces) {
    if (sides.size() == 1) {
      Triangle tri;
      tri.v = sides[0].first;
      tri.back = sides[0].second;
      tri.front = 0;
      const Vec3 n = cross(m.points[tri.v[1]] - m.points[tri.v[0]], m.points[tri.v[2]] - m.points[tri.v[0]]);
      int axis = 0;
      for (int k = 1; k < 3; ++k)
        if (std::abs(n[k]) > std::abs(n[axis])) axis = k;
      tri.face = 1 + 2 * axis + (n[axis] > 0 ? 1 : 0);
      m.triangles.push_back(tri);
    } else if (sides[0].second != sides[1].second) {
      // Normal from region 1 into region 2.
      const auto& s1 = sides[0].second == 1 ? sides[0] : sides[1];
      Triangle tri;
      tri.v = s1.first;
      tri.back = 1;
      tri.front = 2;
      tri.face = 7;
      m.triangles.push_back(tri);
    }
  }
  return m;
}

// Adds a mid node on every edge of every element.
Mesh second_order(Mesh m) {
  std::map<std::pair<int, int>, int> mid;
  auto node = [&](int a, int b) {
    const auto key = std::minmax(a, b);
    auto it = mid.find(key);
    if (it != mid.end()) return it->second;
    m.points.push_back(0.5 * (m.points[a] + m.points[b]));
    const int id = static_cast<int>(m.points.size()) - 1;
    mid.emplace(key, id);
    return id;
  };
  for (const Tetrahedron& t : m.tets) {
    const auto& v = t.v;
    m.tet_mid.push_back({node(v[0], v[1]), node(v[1], v[2]), node(v[2], v[0]), node(v[0], v[3]),
                         node(v[1], v[3]), node(v[2], v[3])});
  }
  for (const Triangle& t : m.triangles) {
    const auto& v = t.v;
    m.triangle_mid.push_back({node(v[0], v[1]), node(v[1], v[2]), node(v[2], v[0])});
  }
  return m;
}

struct Variant {
  std::string file;
  io::WriteOptions options;
  bool triangle_order = true;  // false: triangles compared as a set
  bool sides = true;           // front/back come back
  bool second_order = true;
};

std::string describe(const Variant& v) {
  return v.file + (v.options.binary ? " binary" : " ascii") + " msh" + std::to_string(v.options.msh_version);
}

// A triangle turned so its smallest vertex is first (same orientation).
std::array<int, 3> rotated(std::array<int, 3> v) {
  while (v[0] != std::min({v[0], v[1], v[2]})) v = {v[1], v[2], v[0]};
  return v;
}

using TriRecord = std::tuple<std::array<int, 3>, int, int, int, std::array<int, 3>>;
std::vector<TriRecord> triangle_records(const Mesh& m, bool sides, bool ordered) {
  std::vector<TriRecord> r;
  for (size_t i = 0; i < m.triangles.size(); ++i) {
    const Triangle& t = m.triangles[i];
    std::array<int, 3> mid{-1, -1, -1};
    if (!m.triangle_mid.empty()) {
      // Rotate the mid nodes with the corners.
      std::array<int, 3> v = t.v, md = m.triangle_mid[i];
      while (v[0] != std::min({v[0], v[1], v[2]})) v = {v[1], v[2], v[0]}, md = {md[1], md[2], md[0]};
      mid = md;
    }
    r.emplace_back(rotated(t.v), t.face, sides ? t.front : 0, sides ? t.back : 0, mid);
  }
  if (!ordered) std::sort(r.begin(), r.end());
  return r;
}

void expect_same_volume_mesh(const Mesh& a, const Mesh& b, const Variant& v) {
  SCOPED_TRACE(describe(v));
  ASSERT_EQ(a.points.size(), b.points.size());
  for (size_t i = 0; i < a.points.size(); ++i) {
    EXPECT_EQ(a.points[i].x, b.points[i].x) << "point " << i;
    EXPECT_EQ(a.points[i].y, b.points[i].y) << "point " << i;
    EXPECT_EQ(a.points[i].z, b.points[i].z) << "point " << i;
  }
  ASSERT_EQ(a.tets.size(), b.tets.size());
  for (size_t i = 0; i < a.tets.size(); ++i) {
    EXPECT_EQ(a.tets[i].v, b.tets[i].v) << "tet " << i;
    EXPECT_EQ(a.tets[i].region, b.tets[i].region) << "tet " << i;
    EXPECT_GT(det(b, b.tets[i].v), 0) << "tet " << i;
  }
  ASSERT_EQ(a.tet_mid.size(), b.tet_mid.size());
  for (size_t i = 0; i < a.tet_mid.size(); ++i) EXPECT_EQ(a.tet_mid[i], b.tet_mid[i]) << "tet " << i;
  ASSERT_EQ(a.triangles.size(), b.triangles.size());
  ASSERT_EQ(a.triangle_mid.size(), b.triangle_mid.size());
  EXPECT_EQ(triangle_records(a, v.sides, v.triangle_order), triangle_records(b, v.sides, v.triangle_order));
}

std::vector<Variant> volume_variants() {
  std::vector<Variant> v;
  for (int version : {22, 41})
    for (bool binary : {false, true}) v.push_back({"cube.msh", {binary, version}});
  for (bool binary : {false, true}) {
    v.push_back({"cube.vtk", {binary, 41}});
    v.push_back({"cube.vtu", {binary, 41}});
  }
  v.push_back({"cube.msh.gz", {true, 41}});
  v.push_back({"cube.vtu.gz", {false, 41}});
  v.push_back({"cube.inp", {}, false});
  v.push_back({"cube.mesh", {}, true, true, true});
  v.push_back({"cube.meshb", {}, true, true, true});
  v.push_back({"cube.node", {}});
  return v;
}

TEST(ConvertersRoundTrip, CubeTetsAreValid) {
  const Mesh m = cube_tets();
  EXPECT_EQ(m.tets.size(), 6u);
  int boundary = 0, interface = 0;
  for (const Triangle& t : m.triangles) (t.face == 7 ? interface : boundary)++;
  EXPECT_EQ(boundary, 12);
  EXPECT_EQ(interface, 2);
  for (const Tetrahedron& t : m.tets) EXPECT_GT(det(m, t.v), 0);
}

TEST(ConvertersRoundTrip, VolumeFormatsKeepEverything) {
  const Mesh m = cube_tets();
  for (const Variant& v : volume_variants()) {
    const std::string path = test::temp_path(v.file);
    io::write_mesh(m, path, v.options);
    const Mesh back = io::read_mesh(path);
    expect_same_volume_mesh(m, back, v);
  }
}

// Writers stream through a 1 MiB buffer into FILE.part, renamed at the end:
// a mesh whose files span many buffers must come back the same, and no .part
// may be left behind.
// `copies` unit cubes of tetrahedra side by side: a mesh whose files pass
// the writers' 1 MiB buffer.
Mesh many_cubes(int copies) {
  const Mesh cube = cube_tets();
  Mesh m;
  for (int copy = 0; copy < copies; ++copy) {
    const int base = static_cast<int>(m.points.size());
    // No shift in y: -2.3 + 0.3 + 2 leaves 2.2e-16, which Abaqus' 20-character
    // numbers cannot carry exactly.
    const Vec3 shift{2.0 * (copy % 80), 0.0, 1.0 * (copy / 80)};
    for (const Vec3& p : cube.points) m.points.push_back(p + shift);
    for (Tetrahedron t : cube.tets) {
      for (int& v : t.v) v += base;
      m.tets.push_back(t);
    }
    for (Triangle t : cube.triangles) {
      for (int& v : t.v) v += base;
      m.triangles.push_back(t);
    }
  }
  return m;
}

TEST(ConvertersRoundTrip, LargeMeshesStreamThroughTheBuffer) {
  const Mesh m = many_cubes(4000);
  for (const Variant& v : volume_variants()) {
    const std::string path = test::temp_path("large-" + v.file);
    io::write_mesh(m, path, v.options);
    if (path.size() < 3 || path.substr(path.size() - 3) != ".gz")
      EXPECT_GT(std::filesystem::file_size(path), size_t{1} << 20) << describe(v);
    EXPECT_FALSE(std::filesystem::exists(path + ".part")) << describe(v);
    expect_same_volume_mesh(m, io::read_mesh(path), v);
  }
}

std::string file_text(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// The ASCII arrays are formatted in pieces on several threads
// (write_text_values): the file must not depend on how many.
TEST(ConvertersRoundTrip, TextArraysAreTheSameOnAnyNumberOfThreads) {
  const Mesh m = many_cubes(4000);
  std::string text[2];
  for (int threads : {1, 3}) {
    set_thread_count(threads);
    const std::string path = test::temp_path("threads-" + std::to_string(threads) + ".vtu");
    io::write_mesh(m, path, {});
    text[threads == 1 ? 0 : 1] = file_text(path);
  }
  set_thread_count(0);
  EXPECT_GT(text[0].size(), size_t{1} << 20);
  EXPECT_TRUE(text[0] == text[1]) << "1 thread: " << text[0].size() << " bytes, 3 threads: " << text[1].size();
  // Twelve numbers to a line, as before the pieces: the connectivity's
  // first line is the first three tetrahedra.
  const size_t at = text[0].find("Name=\"connectivity\"");
  ASSERT_NE(at, std::string::npos);
  const size_t line = text[0].find('\n', at) + 1;
  std::istringstream first(text[0].substr(line, text[0].find('\n', line) - line));
  int values = 0;
  for (long long x; first >> x;) ++values;
  EXPECT_EQ(values, 12);
}

TEST(ConvertersRoundTrip, UnwritablePathIsInputErrorAndNoFile) {
  const std::string path = test::temp_path("no-such-folder") + "/cube.vtu";
  EXPECT_THROW(io::write_mesh(cube_tets(), path, {}), InputError);
  EXPECT_FALSE(std::filesystem::exists(path));
  EXPECT_FALSE(std::filesystem::exists(path + ".part"));
}

TEST(ConvertersRoundTrip, SecondOrderVolumeFormats) {
  const Mesh m = second_order(cube_tets());
  // 8 corners + 19 edges (12 cube edges, 6 face diagonals, 1 body diagonal).
  ASSERT_EQ(m.points.size(), 27u);
  for (const Variant& v : volume_variants()) {
    if (!v.second_order) continue;
    const std::string path = test::temp_path("p2." + v.file);
    io::write_mesh(m, path, v.options);
    const Mesh back = io::read_mesh(path);
    expect_same_volume_mesh(m, back, v);
  }
}

// Medit's second order as Gmsh writes it (`gmsh -order 2 -o X.mesh`):
// TetrahedraP2 with the mid-edge nodes in VTK's edge order, not in Gmsh's MSH
// order (the round trip above cannot tell a convention shared by reader and
// writer; a file as Gmsh writes it can).
TEST(ConvertersRoundTrip, MeditSecondOrderIsGmshs) {
  const std::string path = test::temp_path("gmsh_p2.mesh");
  {
    std::ofstream f(path);
    f << "MeshVersionFormatted 2\nDimension\n3\nVertices\n10\n0 0 0 1\n2 0 0 1\n0 2 0 1\n0 0 2 1\n"
         "1 0 0 1\n1 1 0 1\n0 1 0 1\n0 0 1 1\n1 0 1 1\n0 1 1 1\nTetrahedraP2\n1\n1 2 3 4 5 6 7 8 9 10 3\nEnd\n";
  }
  const Mesh m = io::read_mesh(path);
  ASSERT_EQ(m.tet_mid.size(), 1u);
  // vdmesh's edges (01, 12, 20, 03, 13, 23), as Gmsh writes them in .mesh.
  const std::array<std::array<int, 2>, 6> edges = {{{0, 1}, {1, 2}, {2, 0}, {0, 3}, {1, 3}, {2, 3}}};
  for (size_t k = 0; k < 6; ++k) {
    const Vec3 a = m.points[m.tets[0].v[edges[k][0]]], b = m.points[m.tets[0].v[edges[k][1]]];
    const Vec3 mid = m.points[m.tet_mid[0][k]];
    EXPECT_EQ(norm(mid - 0.5 * (a + b)), 0.0) << "edge " << k;
  }
  EXPECT_EQ(m.tets[0].region, 3);
}

// A boundary listed by its corners beside second-order tetrahedra takes the
// tetrahedra's mid-edge nodes (it was written out as first-order triangles
// beside them); second-order triangles beside first-order tetrahedra are
// refused (read as "second order", their nodes belonged to no element).
TEST(ConvertersRoundTrip, MixedOrdersInOneFile) {
  const std::string head =
      "MeshVersionFormatted 2\nDimension\n3\nVertices\n10\n0 0 0 1\n2 0 0 1\n0 2 0 1\n0 0 2 1\n"
      "1 0 0 1\n1 1 0 1\n0 1 0 1\n0 0 1 1\n1 0 1 1\n0 1 1 1\n";
  const std::string p2_tet = "TetrahedraP2\n1\n1 2 3 4 5 6 7 8 9 10 3\n";
  const std::string path = test::temp_path("p1_sides.mesh");
  {
    std::ofstream f(path);
    f << head << "Triangles\n2\n1 3 2 7\n2 3 4 8\n" << p2_tet << "End\n";
  }
  const Mesh m = io::read_mesh(path);
  ASSERT_EQ(m.triangle_mid.size(), 2u);
  for (size_t f = 0; f < 2; ++f)
    for (int e = 0; e < 3; ++e) {
      const Vec3 a = m.points[m.triangles[f].v[e]], b = m.points[m.triangles[f].v[(e + 1) % 3]];
      EXPECT_EQ(norm(m.points[m.triangle_mid[f][e]] - 0.5 * (a + b)), 0.0) << "triangle " << f << " edge " << e;
    }
  const std::string other = test::temp_path("p1_stray.mesh");
  {
    std::ofstream f(other);
    f << "MeshVersionFormatted 2\nDimension\n3\nVertices\n11\n0 0 0 1\n2 0 0 1\n0 2 0 1\n0 0 2 1\n"
         "1 0 0 1\n1 1 0 1\n0 1 0 1\n0 0 1 1\n1 0 1 1\n0 1 1 1\n5 5 5 1\nTriangles\n1\n1 2 11 7\n"
      << p2_tet << "End\n";
  }
  try {
    io::read_mesh(other);
    ADD_FAILURE() << "a triangle off the tetrahedra was read";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("triangle 1 is first order and an edge of it is no edge of the second-order "
                                         "tetrahedra"),
              std::string::npos)
        << e.what();
  }
  const std::string mixed = test::temp_path("p2_sides.mesh");
  {
    std::ofstream f(mixed);
    f << head << "TrianglesP2\n1\n1 3 2 7 6 5 7\nTetrahedra\n1\n1 2 3 4 3\nEnd\n";
  }
  try {
    io::read_mesh(mixed);
    ADD_FAILURE() << "second-order triangles beside first-order tetrahedra were read";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("the triangles are second order and the tetrahedra first order"),
              std::string::npos)
        << e.what();
  }
}

// A TetGen set is replaced whole: a surface written over a volume mesh came
// back with the old .ele (or failed on it). The compressed set and the
// plain one are two sets: writing one leaves the other (converting one into
// the other deleted the input), and each reads without the other's files.
TEST(ConvertersRoundTrip, TetgenSetIsReplacedWhole) {
  const Mesh volume = cube_tets();
  Mesh surface = volume;
  surface.tets.clear();
  const std::string base = test::temp_path("set");
  io::write_mesh(volume, base + ".node");
  ASSERT_TRUE(std::filesystem::exists(base + ".ele"));
  io::write_mesh(surface, base + ".node");
  EXPECT_FALSE(std::filesystem::exists(base + ".ele"));
  Mesh back = io::read_mesh(base + ".node");
  EXPECT_TRUE(back.tets.empty());
  EXPECT_EQ(back.triangles.size(), surface.triangles.size());
  io::write_mesh(volume, base + ".node");
  io::write_mesh(surface, base + ".node.gz");
  for (const char* ext : {".node", ".ele", ".face", ".node.gz", ".face.gz"})
    EXPECT_TRUE(std::filesystem::exists(base + ext)) << ext;
  EXPECT_FALSE(std::filesystem::exists(base + ".ele.gz"));
  back = io::read_mesh(base + ".node.gz");
  EXPECT_TRUE(back.tets.empty());
  EXPECT_EQ(back.triangles.size(), surface.triangles.size());
  EXPECT_EQ(io::read_mesh(base + ".node").tets.size(), volume.tets.size());
  // Only the compressed set there: the base's plain name finds it.
  const std::string lone = test::temp_path("lone");
  io::write_mesh(volume, lone + ".node.gz");
  EXPECT_EQ(io::read_mesh(lone + ".node").tets.size(), volume.tets.size());
  // A plain set whose .ele alone is compressed, with no compressed set
  // beside it: the .ele.gz is its own (it was dropped, 0 tetrahedra).
  const std::string mixed = test::temp_path("mixed"), donor = test::temp_path("donor");
  io::write_mesh(volume, mixed + ".node");
  io::write_mesh(volume, donor + ".node.gz");
  std::filesystem::remove(mixed + ".ele");
  std::filesystem::rename(donor + ".ele.gz", mixed + ".ele.gz");
  EXPECT_EQ(io::read_mesh(mixed + ".node").tets.size(), volume.tets.size());
}

// Two threads writing one path while a third reads it: each write goes to a
// file of its own renamed into place, so a reader finds one whole mesh or
// the other (with one shared PATH.part, reads found the file empty or cut,
// and writes failed with ENOENT).
TEST(ConvertersRoundTrip, ConcurrentWritesOfOnePathStayWhole) {
  const Mesh a = cube_tets();
  Mesh b = a;
  b.tets.resize(b.tets.size() / 2);
  const std::string path = test::temp_path("shared.msh");
  io::write_mesh(a, path);
  std::atomic<bool> stop{false};
  std::atomic<long> failures{0}, reads{0};
  const auto writer = [&](const Mesh& m) {
    for (int i = 0; i < 200; ++i) try {
        io::write_mesh(m, path);
      } catch (const std::exception&) {
        ++failures;
      }
  };
  std::thread reader([&] {
    while (!stop) {
      try {
        const Mesh m = io::read_mesh(path);
        if (m.tets.size() != a.tets.size() && m.tets.size() != b.tets.size()) ++failures;
      } catch (const std::exception&) {
        ++failures;
      }
      ++reads;
    }
  });
  std::thread w1(writer, std::cref(a)), w2(writer, std::cref(b));
  w1.join();
  w2.join();
  stop = true;
  reader.join();
  EXPECT_EQ(failures, 0);
  EXPECT_GT(reads, 10);
  for (const auto& entry : std::filesystem::directory_iterator(std::filesystem::path(path).parent_path()))
    EXPECT_EQ(entry.path().filename().string().find("shared.msh.part"), std::string::npos) << entry.path();
}

// VTK has no place for names: vdmesh keeps them in an array of the data set
// (a CAD mesh's Solid1 came back from a .vtu or a .vtk as Region1).
TEST(ConvertersRoundTrip, VtkFormatsKeepNames) {
  Mesh m = cube_tets();
  m.region_names = {{1, "Solid1"}, {2, "steel part"}};
  m.face_names = {{3, "Face3"}, {-7, "odd"}};
  for (const char* ext : {".vtu", ".vtk"})
    for (bool binary : {false, true}) {
      const std::string path = test::temp_path(std::string(binary ? "names_b" : "names_a") + ext);
      io::write_mesh(m, path, {binary, 41});
      const Mesh back = io::read_mesh(path);
      EXPECT_EQ(back.region_names, m.region_names) << path;
      EXPECT_EQ(back.face_names, m.face_names) << path;
      EXPECT_EQ(back.tets.size(), m.tets.size()) << path;
    }
}

// A volume mesh written to a surface format lists its boundary's points
// only: its interior points were isolated vertices of the OFF and OBJ files
// (647 vertices for 185 triangles), and points TetGen had to keep in a .poly.
TEST(ConvertersRoundTrip, SurfaceFormatsOfAVolumeMeshListTheBoundaryPoints) {
  Mesh m = cube_tets();
  // A point no triangle uses, first: the others' numbers change.
  m.points.insert(m.points.begin(), {0.5, 0.5, 0.5});
  for (Triangle& t : m.triangles)
    for (int& v : t.v) ++v;
  for (Tetrahedron& t : m.tets)
    for (int& v : t.v) ++v;
  std::set<int> used;
  for (const Triangle& t : m.triangles) used.insert(t.v.begin(), t.v.end());
  ASSERT_LT(used.size(), m.points.size());
  for (const char* ext : {".off", ".obj", ".poly"}) {
    const std::string path = test::temp_path(std::string("boundary") + ext);
    io::write_mesh(m, path);
    const Mesh back = io::read_mesh(path);
    EXPECT_EQ(back.points.size(), used.size()) << ext;
    ASSERT_EQ(back.triangles.size(), m.triangles.size()) << ext;
    double area_in = 0, area_back = 0;
    for (const Triangle& t : m.triangles)
      area_in += norm(cross(m.points[t.v[1]] - m.points[t.v[0]], m.points[t.v[2]] - m.points[t.v[0]]));
    for (const Triangle& t : back.triangles)
      area_back += norm(cross(back.points[t.v[1]] - back.points[t.v[0]], back.points[t.v[2]] - back.points[t.v[0]]));
    EXPECT_NEAR(area_back, area_in, 1e-12 * area_in) << ext;
  }
}

// Names that carry no id (Zeta, not Region1 or Solid1) keep their ids
// through an Abaqus deck, given in comments: they were numbered by their
// lowest element, and with region 2's tetrahedra first Zeta (1) came back 2.
TEST(ConvertersRoundTrip, AbaqusKeepsTheIdsOfNamedSets) {
  Mesh m = cube_tets();
  std::stable_sort(m.tets.begin(), m.tets.end(),
                   [](const Tetrahedron& a, const Tetrahedron& b) { return a.region > b.region; });
  m.region_names = {{1, "Zeta"}, {2, "Alpha"}};
  std::set<int> faces;
  for (const Triangle& t : m.triangles) faces.insert(t.face);
  ASSERT_GE(faces.size(), 2u);
  const int f1 = *faces.begin(), f2 = *std::next(faces.begin());
  m.face_names = {{f1, "wall"}, {f2, "contact"}};
  const std::string path = test::temp_path("named_ids.inp");
  io::write_mesh(m, path);
  const Mesh back = io::read_mesh(path);
  EXPECT_EQ(back.region_names, m.region_names);
  EXPECT_EQ(back.face_names.at(f1), "wall");
  EXPECT_EQ(back.face_names.at(f2), "contact");
  std::map<int, size_t> count_in, count_back;
  for (const Tetrahedron& t : m.tets) ++count_in[t.region];
  for (const Tetrahedron& t : back.tets) ++count_back[t.region];
  EXPECT_EQ(count_back, count_in);
  // A name that looks like another id: the comment wins (region 1 named
  // Region2 came back as region 2, and Beta as 3).
  m.region_names = {{1, "Region2"}, {2, "Beta"}};
  io::write_mesh(m, path);
  const Mesh again = io::read_mesh(path);
  EXPECT_EQ(again.region_names, m.region_names);
  std::map<int, size_t> count_again;
  for (const Tetrahedron& t : again.tets) ++count_again[t.region];
  EXPECT_EQ(count_again, count_in);
}

// On an interface each face's *SURFACE names its own solid's element sides:
// its solid from its facets on the exterior, or for a face glued whole the
// other side from its partner's solid (the numbering rule gave both the
// same solid where the partner was known otherwise, a review's case).
TEST(ConvertersRoundTrip, AbaqusInterfaceSurfacesNameTheirOwnSolid) {
  Mesh m = cube_tets();
  int interface = -1;
  for (Triangle& t : m.triangles) {
    if (t.front > 0 && t.back > 0) interface = t.face;
    else if (t.back == 1 || t.front == 1) t.face = 20;  // region 1's outside, in group 20
  }
  ASSERT_GE(interface, 0);
  m.face_groups[interface] = {5, 20};
  m.face_names = {{5, "Glued"}, {20, "Outer"}};
  const std::string path = test::temp_path("interface_sides.inp");
  io::write_mesh(m, path);
  // Element -> region, and each *SURFACE's elements on the interface.
  std::ifstream in(path);
  std::map<int, std::string> set_of;
  std::map<std::string, std::set<std::string>> sets_of_surface;
  std::string line, elset, surface;
  std::set<int> interface_elements;
  for (size_t i = 0; i < m.tets.size(); ++i) {
    int on = 0;
    for (const Triangle& t : m.triangles)
      if (t.face == interface) {
        std::set<int> tv(t.v.begin(), t.v.end()), vv(m.tets[i].v.begin(), m.tets[i].v.end());
        on |= std::includes(vv.begin(), vv.end(), tv.begin(), tv.end());
      }
    if (on) interface_elements.insert(static_cast<int>(i) + 1);
  }
  while (std::getline(in, line)) {
    if (line.rfind("*ELEMENT", 0) == 0) elset = line.substr(line.find("ELSET=") + 6), surface.clear();
    else if (line.rfind("*SURFACE", 0) == 0) surface = line.substr(line.find("NAME=") + 5, line.find(',', line.find("NAME=")) - line.find("NAME=") - 5), elset.clear();
    else if (line.rfind("*", 0) == 0) elset.clear(), surface.clear();
    else if (!elset.empty()) set_of[std::stoi(line)] = elset;
    else if (!surface.empty() && interface_elements.count(std::stoi(line))) sets_of_surface[surface].insert(set_of.at(std::stoi(line)));
  }
  EXPECT_EQ(sets_of_surface["Outer"], std::set<std::string>{"Region1"});
  EXPECT_EQ(sets_of_surface["Glued"], std::set<std::string>{"Region2"});
}

// A second-order surface whose triangles a reader turns to one side (Gmsh
// files without volumes): the mid-edge nodes turn with the corners. They
// stayed, on other edges, and the mid-node check refused such a file.
TEST(ConvertersRoundTrip, TurnedSecondOrderTrianglesKeepTheirMidNodes) {
  Mesh m = shapes::box({0, 0, 0}, {1, 1, 1}, 2);
  make_second_order(m);
  for (size_t f = 0; f < m.triangles.size(); f += 3) {  // a third turned in
    std::swap(m.triangles[f].v[1], m.triangles[f].v[2]);
    std::swap(m.triangle_mid[f][0], m.triangle_mid[f][2]);
  }
  for (int version : {22, 41}) {
    const std::string path = test::temp_path("turned_p2_" + std::to_string(version) + ".msh");
    io::write_mesh(m, path, {false, version});
    const Mesh back = io::read_mesh(path);
    ASSERT_EQ(back.triangle_mid.size(), m.triangles.size());
    for (size_t f = 0; f < back.triangles.size(); ++f)
      for (int e = 0; e < 3; ++e) {
        const Vec3 a = back.points[back.triangles[f].v[e]], b = back.points[back.triangles[f].v[(e + 1) % 3]];
        EXPECT_EQ(norm(back.points[back.triangle_mid[f][e]] - 0.5 * (a + b)), 0.0) << version << " triangle " << f;
      }
  }
}

// Parts left beside a file by writes of processes that are gone are removed
// at the next write, once untouched for ten minutes; a running process's,
// fresh ones and a user's files of similar names are not.
TEST(ConvertersRoundTrip, StalePartsOfDeadWritersAreRemoved) {
  namespace fs = std::filesystem;
  const std::string path = test::temp_path("stale.msh");
  const pid_t child = fork();
  if (child == 0) _exit(0);
  ASSERT_GT(child, 0);
  waitpid(child, nullptr, 0);
  const std::string dead = path + ".part." + std::to_string(child) + ".0";
  const std::string dead_folder = path + ".part." + std::to_string(child) + ".Ab12Cd";
  const std::string fresh = path + ".part." + std::to_string(child) + ".1";
  const std::string alive = path + ".part." + std::to_string(getppid()) + ".0";
  const std::string users = path + ".part." + std::to_string(child) + ".txt";
  const std::string users_folder = path + ".part." + std::to_string(child) + ".d";
  for (const std::string& f : {dead, fresh, alive, users}) std::ofstream(f) << "cut";
  fs::create_directory(dead_folder);
  fs::create_directory(users_folder);
  std::ofstream(dead_folder + "/stale.msh") << "cut";
  const auto old = fs::file_time_type::clock::now() - std::chrono::hours(1);
  for (const std::string& f : {dead, dead_folder, dead_folder + "/stale.msh", alive, users, users_folder})
    fs::last_write_time(f, old);
  io::write_mesh(cube_tets(), path);
  EXPECT_FALSE(fs::exists(dead));
  EXPECT_FALSE(fs::exists(dead_folder));
  for (const std::string& f : {fresh, alive, users, users_folder}) {
    EXPECT_TRUE(fs::exists(f)) << f;
    fs::remove_all(f);
  }
}

TEST(ConvertersRoundTrip, GmshKeepsNamesAndSparseTags) {
  Mesh m = cube_tets();
  for (Tetrahedron& t : m.tets) t.region = t.region == 1 ? 10 : 20;
  for (Triangle& t : m.triangles) {
    for (int* side : {&t.front, &t.back})
      if (*side > 0) *side = *side == 1 ? 10 : 20;
    t.face += 100;
  }
  m.region_names[10] = "steel";
  m.face_names[107] = "contact";
  for (int version : {22, 41})
    for (bool binary : {false, true}) {
      const Variant v{"names.msh", {binary, version}};
      const std::string path = test::temp_path("v" + std::to_string(version) + (binary ? "b" : "a") + ".msh");
      io::write_mesh(m, path, v.options);
      const Mesh back = io::read_mesh(path);
      expect_same_volume_mesh(m, back, v);
      EXPECT_EQ(back.region_names.at(10), "steel");
      EXPECT_EQ(back.region_names.at(20), "Region20");
      EXPECT_EQ(back.face_names.at(107), "contact");
      EXPECT_EQ(back.face_names.at(101), "Face101");
    }
}

// A binary MSH 4.1 file by hand: two tetrahedra on five nodes, in the
// element blocks given as (entity, {tag, tag, ...}) with tetrahedron i of
// the list (in file order) taking nodes kTets[i].
std::string binary_msh41(const std::string& name, const std::vector<std::pair<int, std::vector<uint64_t>>>& blocks) {
  static const uint64_t kTets[2][4] = {{1, 2, 3, 4}, {2, 1, 3, 5}};
  std::string b = "$MeshFormat\n4.1 1 8\n";
  auto put = [&](const auto& v) { b.append(reinterpret_cast<const char*>(&v), sizeof v); };
  put(int32_t{1});
  b += "\n$EndMeshFormat\n$Nodes\n";
  const double xyz[5][3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {0, 0, -1}};
  put(uint64_t{1}), put(uint64_t{5}), put(uint64_t{1}), put(uint64_t{5});
  put(int32_t{3}), put(int32_t{1}), put(int32_t{0}), put(uint64_t{5});
  for (uint64_t t = 1; t <= 5; ++t) put(t);
  for (const auto& p : xyz) b.append(reinterpret_cast<const char*>(p), sizeof p);
  b += "\n$EndNodes\n$Elements\n";
  uint64_t lo = UINT64_MAX, hi = 0;
  for (const auto& blk : blocks)
    for (uint64_t t : blk.second) lo = std::min(lo, t), hi = std::max(hi, t);
  put(uint64_t{blocks.size()}), put(uint64_t{2}), put(lo), put(hi);
  size_t next = 0;
  for (const auto& [entity, tags] : blocks) {
    put(int32_t{3}), put(int32_t{entity}), put(int32_t{4}), put(uint64_t{tags.size()});
    for (uint64_t t : tags) {
      put(t);
      for (uint64_t v : kTets[next]) put(v);
      ++next;
    }
  }
  b += "\n$EndElements\n";
  const std::string path = test::temp_path(name);
  std::ofstream(path, std::ios::binary) << b;
  return path;
}

// Tetrahedra come out in tag order whatever the tags look like: a range in
// two blocks (placed by tag while reading), gaps, and a repeated tag (kept in
// file order).
TEST(ConvertersRoundTrip, BinaryMsh41PutsTetrahedraInTagOrder) {
  const std::array<int, 4> first{0, 1, 2, 3}, second{1, 0, 2, 4};
  {
    const Mesh m = io::read_mesh(binary_msh41("range.msh", {{1, {2}}, {2, {1}}}));
    ASSERT_EQ(m.tets.size(), 2u);
    EXPECT_EQ(m.tets[0].v, second);
    EXPECT_EQ(m.tets[0].region, 2);
    EXPECT_EQ(m.tets[1].v, first);
    EXPECT_EQ(m.tets[1].region, 1);
  }
  {
    const Mesh m = io::read_mesh(binary_msh41("gaps.msh", {{1, {70, 30}}}));
    ASSERT_EQ(m.tets.size(), 2u);
    EXPECT_EQ(m.tets[0].v, second);
    EXPECT_EQ(m.tets[1].v, first);
  }
  {
    const Mesh m = io::read_mesh(binary_msh41("repeat.msh", {{4, {5}}, {3, {5}}}));
    ASSERT_EQ(m.tets.size(), 2u);
    EXPECT_EQ(m.tets[0].v, first);
    EXPECT_EQ(m.tets[0].region, 4);
    EXPECT_EQ(m.tets[1].v, second);
  }
}

// Gmsh's 2.2 writer repeats an element under the next number for each
// further physical group of its entity: read once, in its first group (two
// tetrahedra, a third region and twice the volume before 2026-11-30).
TEST(ConvertersRoundTrip, Msh22ElementInTwoPhysicalGroupsIsReadOnce) {
  const std::string path = test::temp_path("two_groups.msh");
  std::ofstream(path) << "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n5\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n"
                         "5 1 1 1\n$EndNodes\n$Elements\n4\n7 4 2 11 1 1 2 3 4\n8 4 2 99 1 1 2 3 4\n"
                         "9 4 2 22 2 2 3 4 5\n10 4 2 99 2 2 3 4 5\n$EndElements\n";
  const Mesh m = io::read_mesh(path);
  ASSERT_EQ(m.tets.size(), 2u);
  EXPECT_EQ(m.tets[0].region, 11);
  EXPECT_EQ(m.tets[1].region, 22);
}

// Medit reference 0 on a tetrahedron is "none" (TetGen's -g, meshio without
// cell data), not the exterior: "region 0: volume 2" until 2026-11-30.
TEST(ConvertersRoundTrip, MeditReferenceZeroIsNoRegion) {
  const std::string path = test::temp_path("ref0.mesh");
  std::ofstream(path) << "MeshVersionFormatted 1\nDimension 3\nVertices\n5\n0 0 0 0\n1 0 0 0\n0 1 0 0\n0 0 1 0\n"
                         "1 1 1 0\nTetrahedra\n2\n1 2 3 4 0\n2 3 4 5 0\nEnd\n";
  const Mesh m = io::read_mesh(path);
  ASSERT_EQ(m.tets.size(), 2u);
  for (const Tetrahedron& t : m.tets) EXPECT_EQ(t.region, kUnknownRegion);
}

TEST(ConvertersRoundTrip, AbaqusRegionNamesAndSets) {
  Mesh m = cube_tets();
  m.region_names[2] = "Copper";
  const std::string path = test::temp_path("named.inp");
  io::write_mesh(m, path);
  const Mesh back = io::read_mesh(path);
  ASSERT_EQ(back.tets.size(), m.tets.size());
  // Region 1 keeps its id (ELSET Region1); "Copper" gets the next free id.
  std::set<int> regions;
  for (size_t i = 0; i < m.tets.size(); ++i) {
    EXPECT_EQ(back.tets[i].v, m.tets[i].v);
    if (m.tets[i].region == 1) EXPECT_EQ(back.tets[i].region, 1);
    else EXPECT_EQ(back.region_names.at(back.tets[i].region), "Copper");
    regions.insert(back.tets[i].region);
  }
  EXPECT_EQ(regions.size(), 2u);
}

// Names that sanitize or upper-case to one set, and names over CalculiX's
// 80 characters, get sets of their own that CalculiX takes: "part A" and
// "part_A", "Steel" and "steel" were one region read back, and a 101-letter
// name stopped ccx ("set name too long"), until 2026-11-30.
TEST(ConvertersRoundTrip, AbaqusSetNamesStayApartAndShort) {
  Mesh m = cube_tets();
  const std::string longest(101, 'L');
  const std::vector<std::string> wanted = {"part A", "part_A", "Steel", "steel", longest, longest + "2"};
  for (size_t i = 0; i < m.tets.size(); ++i) {
    m.tets[i].region = static_cast<int>(i) + 1;
    m.region_names[static_cast<int>(i) + 1] = wanted[i];
  }
  ASSERT_FALSE(m.triangles.empty());
  for (Triangle& t : m.triangles) {
    t.front = 0;
    t.back = m.tets[0].region;
    m.face_names[t.face] = longest + "face" + std::to_string(t.face);
  }
  const std::string path = test::temp_path("names.inp");
  io::write_mesh(m, path);
  std::ifstream in(path);
  int nsets = 0;
  for (std::string line; std::getline(in, line);)
    for (const char* key : {"ELSET=", "NSET=", "NAME="}) {
      const size_t at = line.find(key);
      if (at == std::string::npos) continue;
      const size_t start = at + std::string(key).size();
      const size_t end = line.find(',', start);
      EXPECT_LE((end == std::string::npos ? line.size() : end) - start, 80u) << line;
      nsets += std::string(key) == "NSET=" && line.find("NALL") == std::string::npos;
    }
  EXPECT_GT(nsets, 0);
  const Mesh back = io::read_mesh(path);
  std::set<int> regions;
  for (const Tetrahedron& t : back.tets) regions.insert(t.region);
  EXPECT_EQ(regions.size(), 6u);
}

// Regions of decks other programs write: a material's elements are listed
// in an *ELSET apart from the element block and named by *SOLID SECTION
// (CalculiX, Abaqus/CAE), or include the block's set by name (FreeCAD);
// without sections, *ELSETs of tetrahedra only that cover each once (Gmsh's
// physical groups). Two materials were read as one region until 2026-11-29.
namespace abaqus_decks {
const char* const kNodes = "*NODE\n1, 0, 0, 0\n2, 1, 0, 0\n3, 0, 1, 0\n4, 0, 0, 1\n5, 1, 1, 1\n";
// Volumes 1/6 (element 1) and 1/3 (element 2).
std::map<std::string, double> volumes_by_name(const std::string& deck, const std::string& name) {
  const std::string path = test::temp_path(name);
  std::ofstream(path) << kNodes << deck;
  const Mesh m = io::read_mesh(path);
  std::map<std::string, double> out;
  for (const Tetrahedron& t : m.tets) {
    const auto it = m.region_names.find(t.region);
    out[it == m.region_names.end() ? "#" + std::to_string(t.region) : it->second] +=
        std::abs(dot(cross(m.points[t.v[1]] - m.points[t.v[0]], m.points[t.v[2]] - m.points[t.v[0]]),
                     m.points[t.v[3]] - m.points[t.v[0]])) / 6;
  }
  return out;
}
}  // namespace abaqus_decks

// A facet in two faces' groups (an interface of two CAD faces) is one
// facet on both, however a file lists it: an Abaqus deck through each
// solid's own element (two facets, duplicates, until 2026-11-30), a Gmsh
// 4.1 entity with two physical surfaces beside a named group without
// elements (the shared piece took that group's number, 3 "Outlet").
TEST(ConvertersRoundTrip, FacetsInTwoFaceGroupsAreReadOnce) {
  const std::string deck = test::temp_path("shared_sides.inp");
  std::ofstream(deck) << abaqus_decks::kNodes
                      << "*ELEMENT, TYPE=C3D4, ELSET=Solid1\n1, 1, 2, 3, 4\n*ELEMENT, TYPE=C3D4, ELSET=Solid2\n"
                         "2, 2, 3, 4, 5\n*SURFACE, NAME=Face1, TYPE=ELEMENT\n1, S3\n"
                         "*SURFACE, NAME=Face2, TYPE=ELEMENT\n2, S1\n*SURFACE, NAME=Face3, TYPE=ELEMENT\n1, S1\n";
  const Mesh a = io::read_mesh(deck);
  ASSERT_EQ(a.triangles.size(), 2u);
  const std::map<int, std::vector<int>> shared{{1, {1, 2}}};
  EXPECT_EQ(a.face_groups, shared);
  const std::string msh = test::temp_path("shared_entity.msh");
  std::ofstream(msh) << "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$PhysicalNames\n4\n2 1 \"A\"\n2 2 \"B\"\n"
                        "2 3 \"Outlet\"\n3 1 \"Region1\"\n$EndPhysicalNames\n$Entities\n0 0 3 1\n"
                        "1 0 0 0 1 1 1 1 1 0\n2 0 0 0 1 1 1 1 2 0\n3 0 0 0 1 1 1 2 2 1 0\n"
                        "1 0 0 0 1 1 1 1 1 0\n$EndEntities\n$Nodes\n1 4 1 4\n3 1 0 4\n1\n2\n3\n4\n"
                        "0 0 0\n1 0 0\n0 1 0\n0 0 1\n$EndNodes\n$Elements\n4 4 1 4\n2 1 2 1\n1 1 3 2\n"
                        "2 2 2 1\n2 1 2 4\n2 3 2 1\n3 1 4 3\n3 1 4 1\n4 1 2 3 4\n$EndElements\n";
  const Mesh g = io::read_mesh(msh);
  ASSERT_EQ(g.triangles.size(), 3u);
  const Triangle& piece = g.triangles[2];
  EXPECT_TRUE(piece.face != 1 && piece.face != 2 && piece.face != 3) << piece.face;
  const std::map<int, std::vector<int>> entity{{piece.face, {2, 1}}};
  EXPECT_EQ(g.face_groups, entity);
}

TEST(ConvertersRoundTrip, AbaqusRegionsFromSolidSectionsAndElementSets) {
  using abaqus_decks::volumes_by_name;
  const auto calculix = volumes_by_name(
      "*ELEMENT, TYPE=C3D4, ELSET=EALL\n1, 1, 2, 3, 4\n2, 2, 3, 4, 5\n*ELSET, ELSET=STEEL\n1\n"
      "*ELSET, ELSET=ALU, GENERATE\n2, 2, 1\n*MATERIAL, NAME=STEEL\n*SOLID SECTION, ELSET=STEEL, MATERIAL=STEEL\n"
      "*Solid Section, elset=alu, material=ALU\n",
      "calculix.inp");
  EXPECT_EQ(calculix.size(), 2u);
  EXPECT_NEAR(calculix.at("STEEL"), 1.0 / 6, 1e-15);
  EXPECT_NEAR(calculix.at("ALU"), 1.0 / 3, 1e-15);
  // Sets naming other sets, as FreeCAD's decks do.
  const auto nested = volumes_by_name(
      "*ELEMENT, TYPE=C3D4, ELSET=E1\n1, 1, 2, 3, 4\n*ELEMENT, TYPE=C3D4, ELSET=E2\n2, 2, 3, 4, 5\n"
      "*ELSET,ELSET=MaterialSteel\nE1\n*ELSET,ELSET=MaterialAlu\nE2,\n"
      "*SOLID SECTION, ELSET=MaterialSteel, MATERIAL=Steel\n*SOLID SECTION, ELSET=MaterialAlu, MATERIAL=Alu\n",
      "nested.inp");
  EXPECT_EQ(nested.size(), 2u);
  EXPECT_NEAR(nested.at("MaterialSteel"), 1.0 / 6, 1e-15);
  EXPECT_NEAR(nested.at("MaterialAlu"), 1.0 / 3, 1e-15);
  // A set holding every tetrahedron (a deck's EALL, one material for all)
  // says nothing of regions: vdmesh's own blocks stand. Sections naming a
  // set defined nowhere, or a shell block, are passed over (they ended in
  // "internal error: map::at").
  const auto eall = volumes_by_name(
      "*ELEMENT, TYPE=C3D4, ELSET=Region1\n1, 1, 2, 3, 4\n*ELEMENT, TYPE=C3D4, ELSET=Region2\n2, 2, 3, 4, 5\n"
      "*ELEMENT, TYPE=CPS3, ELSET=Plate\n10, 1, 3, 2\n*ELSET, ELSET=EALL, GENERATE\n1, 2\n"
      "*SOLID SECTION, ELSET=EALL, MATERIAL=Steel\n*SOLID SECTION, ELSET=Plate, MATERIAL=Steel\n"
      "*SOLID SECTION, ELSET=Nowhere, MATERIAL=Steel\n",
      "eall.inp");
  EXPECT_EQ(eall.size(), 2u);
  EXPECT_NEAR(eall.at("#1"), 1.0 / 6, 1e-15);
  EXPECT_NEAR(eall.at("#2"), 1.0 / 3, 1e-15);
  // Element blocks without a set (Abaqus/CAE's parts): the one section names the region.
  const auto cae = volumes_by_name(
      "*Element, type=C3D4\n1, 1, 2, 3, 4\n2, 2, 3, 4, 5\n*Elset, elset=Set-1, generate\n1, 2, 1\n"
      "*Solid Section, elset=Set-1, material=Material-1\n",
      "cae.inp");
  EXPECT_EQ(cae.size(), 1u);
  EXPECT_NEAR(cae.at("Set-1"), 0.5, 1e-15);
  // A chain of sets each naming the next resolves each set once.
  std::string chain = "*ELEMENT, TYPE=C3D4, ELSET=Region1\n1, 1, 2, 3, 4\n2, 2, 3, 4, 5\n";
  for (int k = 0; k < 4000; ++k) chain += "*ELSET, ELSET=S" + std::to_string(k) + "\nS" + std::to_string(k + 1) + "\n";
  EXPECT_EQ(volumes_by_name(chain, "chain.inp").size(), 1u);
  // Abaqus/CAE: one part placed once, where it was made.
  const auto part = volumes_by_name(
      "*Part, name=Bracket\n*Element, type=C3D4\n1, 1, 2, 3, 4\n2, 2, 3, 4, 5\n*Elset, elset=Set-1, generate\n1, 2, 1\n"
      "*Solid Section, elset=Set-1, material=Steel\n*End Part\n*Assembly, name=Assembly\n"
      "*Instance, name=Bracket-1, part=Bracket\n*End Instance\n*End Assembly\n",
      "part.inp");
  EXPECT_NEAR(part.at("Set-1"), 0.5, 1e-15);
  // Heat transfer tetrahedra are tetrahedra (skipped before 2026-11-30).
  const auto heat = volumes_by_name("*ELEMENT, TYPE=DC3D4, ELSET=Copper\n1, 1, 2, 3, 4\n2, 2, 3, 4, 5\n", "heat.inp");
  EXPECT_NEAR(heat.at("Copper"), 0.5, 1e-15);
  // CAD solids keep their numbers: Solid2 is region 2 though its elements come first.
  {
    const std::string path = test::temp_path("solids.inp");
    std::ofstream(path) << abaqus_decks::kNodes
                        << "*ELEMENT, TYPE=C3D4, ELSET=Solid2\n1, 1, 2, 3, 4\n*ELEMENT, TYPE=C3D4, ELSET=Solid1\n"
                           "2, 2, 3, 4, 5\n";
    const Mesh m = io::read_mesh(path);
    ASSERT_EQ(m.tets.size(), 2u);
    EXPECT_EQ(m.tets[0].region, 2);
    EXPECT_EQ(m.tets[1].region, 1);
    EXPECT_EQ(m.region_names.at(2), "Solid2");
  }
  // Set names are not case-sensitive.
  const auto cases = volumes_by_name(
      "*Element, type=C3D4, elset=Steel\n1, 1, 2, 3, 4\n*Element, type=C3D4, elset=STEEL\n2, 2, 3, 4, 5\n", "case.inp");
  EXPECT_EQ(cases.size(), 1u);
  EXPECT_NEAR(cases.at("Steel"), 0.5, 1e-15);
  // Gmsh: the blocks are its entities, the *ELSETs its physical groups; its
  // physical surfaces come as CPS3 blocks and are the boundary's faces.
  const std::string gmsh =
      "*ELEMENT, type=CPS3, ELSET=Surface1\n10, 1, 3, 2\n*ELEMENT, type=C3D4, ELSET=Volume1\n1, 1, 2, 3, 4\n"
      "2, 2, 3, 4, 5\n*ELSET,ELSET=bottom\n10,\n*ELSET,ELSET=inner\n1,\n*ELSET,ELSET=outer\n2,\n";
  const auto by_group = volumes_by_name(gmsh, "gmsh.inp");
  EXPECT_EQ(by_group.size(), 2u);
  EXPECT_NEAR(by_group.at("inner"), 1.0 / 6, 1e-15);
  EXPECT_NEAR(by_group.at("outer"), 1.0 / 3, 1e-15);
  const Mesh m = io::read_mesh(test::temp_path("gmsh.inp"));
  ASSERT_EQ(m.triangles.size(), 1u);
  EXPECT_EQ(m.face_names.at(m.triangles[0].face), "Surface1");
  // Sets that do not cover each tetrahedron once are no regions: the blocks stand.
  const auto partial = volumes_by_name(
      "*ELEMENT, TYPE=C3D4, ELSET=Region1\n1, 1, 2, 3, 4\n*ELEMENT, TYPE=C3D4, ELSET=Region2\n2, 2, 3, 4, 5\n"
      "*ELSET, ELSET=PRINTED\n1\n",
      "partial.inp");
  EXPECT_EQ(partial.size(), 2u);
  EXPECT_NEAR(partial.at("#1"), 1.0 / 6, 1e-15);
  EXPECT_NEAR(partial.at("#2"), 1.0 / 3, 1e-15);
}

// *INCLUDE, as split decks use it (FreeCAD's "split input", Abaqus/CAE's
// parts): files named relative to the including one, data lines of the
// keyword before the *INCLUDE going on in the included file and after it,
// files nesting. Refused as "not supported" until 2026-11-30.
TEST(ConvertersRoundTrip, AbaqusIncludedFiles) {
  namespace fs = std::filesystem;
  const fs::path dir = test::temp_path("include_deck");
  fs::create_directories(dir / "parts");
  std::ofstream(dir / "nodes.inp") << "** nodes alone\n1, 0, 0, 0\n2, 1, 0, 0\n3, 0, 1, 0\n";
  std::ofstream(dir / "parts" / "elements.inp")
      << "*ELEMENT, TYPE=C3D4, ELSET=Inner\n1, 1, 2, 3, 4\n*INCLUDE, INPUT=outer.inp\n";
  std::ofstream(dir / "parts" / "outer.inp") << "*ELEMENT, TYPE=C3D4, ELSET=Outer\n2, 2, 3, 4, 5\n";
  std::ofstream(dir / "deck.inp") << "*HEADING\nsplit deck\n*NODE, NSET=NALL\n*INCLUDE, INPUT=nodes.inp\n"
                                     "4, 0, 0, 1\n5, 1, 1, 1\n*INCLUDE, INPUT=\"parts/elements.inp\"\n"
                                     "*SURFACE, NAME=Bottom, TYPE=ELEMENT\n1, S1\n";
  const Mesh m = io::read_mesh((dir / "deck.inp").string());
  ASSERT_EQ(m.points.size(), 5u);
  ASSERT_EQ(m.tets.size(), 2u);
  std::map<std::string, double> volume;
  for (const Tetrahedron& t : m.tets)
    volume[m.region_names.at(t.region)] +=
        std::abs(dot(cross(m.points[t.v[1]] - m.points[t.v[0]], m.points[t.v[2]] - m.points[t.v[0]]),
                     m.points[t.v[3]] - m.points[t.v[0]])) / 6;
  EXPECT_NEAR(volume.at("Inner"), 1.0 / 6, 1e-15);
  EXPECT_NEAR(volume.at("Outer"), 1.0 / 3, 1e-15);
  ASSERT_EQ(m.triangles.size(), 1u);
  EXPECT_EQ(m.face_names.at(m.triangles[0].face), "Bottom");
  // An error inside an included file names that file and its line.
  std::ofstream(dir / "nodes.inp") << "1, 0, 0, 0\n2, 1, zero, 0\n";
  try {
    io::read_mesh((dir / "deck.inp").string());
    ADD_FAILURE() << "a bad coordinate in an included file was read";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()).rfind((dir / "nodes.inp").string() + ":2: ", 0), 0u) << e.what();
  }
}

// The real TetGen: `tetgen -pq1.4o2` on a unit box, read back. Every mid node
// must sit on the mid-point of the edge vdmesh's order names (01, 12, 20, 03,
// 13, 23 for tetrahedra, 01, 12, 20 for faces), and writing the mesh again
// must give TetGen's own node columns.
const char* const kBoxPoly =
    "8 3 0 0\n1 0 0 0\n2 1 0 0\n3 1 1 0\n4 0 1 0\n5 0 0 1\n6 1 0 1\n7 1 1 1\n8 0 1 1\n"
    "6 1\n1 0 1\n4 1 2 3 4\n1 0 2\n4 5 6 7 8\n1 0 3\n4 1 2 6 5\n1 0 4\n4 2 3 7 6\n1 0 5\n4 3 4 8 7\n"
    "1 0 6\n4 4 1 5 8\n0\n0\n";

// The rows of a TetGen file without comments and the header, as fields.
std::vector<std::vector<std::string>> tetgen_rows(const std::string& path) {
  std::ifstream in(path);
  std::vector<std::vector<std::string>> rows;
  std::string line;
  while (std::getline(in, line)) {
    line = line.substr(0, line.find('#'));
    std::istringstream fields(line);
    std::vector<std::string> row;
    for (std::string f; fields >> f;) row.push_back(f);
    if (!row.empty()) rows.push_back(row);
  }
  if (!rows.empty()) rows.erase(rows.begin());
  return rows;
}

void expect_mid_point(const Mesh& m, int mid, int a, int b, const std::string& what) {
  const Vec3 expected = 0.5 * (m.points[a] + m.points[b]);
  // TetGen prints coordinates with 16 significant digits.
  EXPECT_LT(norm(m.points[mid] - expected), 1e-14) << what;
}

TEST(ConvertersRoundTrip, ReadsRealTetgenSecondOrder) {
  if (std::system("command -v tetgen > /dev/null 2>&1") != 0)
    GTEST_SKIP() << "tetgen not found (Resources/tools/install-deps.sh installs it)";
  const std::filesystem::path dir = test::temp_path("tetgen_o2");
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  std::ofstream(dir / "box.poly") << kBoxPoly;
  const std::string run = "cd '" + dir.string() + "' && tetgen -pq1.4o2a0.05Q box.poly > tetgen.log 2>&1";
  ASSERT_EQ(std::system(run.c_str()), 0) << run;

  const Mesh m = io::read_mesh((dir / "box.1.node").string());
  ASSERT_GT(m.tets.size(), 20u);
  ASSERT_EQ(m.tet_mid.size(), m.tets.size());
  ASSERT_EQ(m.triangle_mid.size(), m.triangles.size());
  double volume = 0;
  for (size_t i = 0; i < m.tets.size(); ++i) {
    const auto& v = m.tets[i].v;
    const auto& mid = m.tet_mid[i];
    const std::string what = "tetrahedron " + std::to_string(i);
    const int edges[6][2] = {{0, 1}, {1, 2}, {2, 0}, {0, 3}, {1, 3}, {2, 3}};
    for (int k = 0; k < 6; ++k) expect_mid_point(m, mid[k], v[edges[k][0]], v[edges[k][1]], what);
    EXPECT_GT(det(m, v), 0) << what;
    volume += det(m, v) / 6;
  }
  EXPECT_NEAR(volume, 1.0, 1e-12);
  std::set<int> faces;
  for (size_t i = 0; i < m.triangles.size(); ++i) {
    const auto& v = m.triangles[i].v;
    const auto& mid = m.triangle_mid[i];
    const std::string what = "triangle " + std::to_string(i);
    for (int k = 0; k < 3; ++k) expect_mid_point(m, mid[k], v[k], v[(k + 1) % 3], what);
    faces.insert(m.triangles[i].face);
  }
  EXPECT_EQ(faces, (std::set<int>{1, 2, 3, 4, 5, 6}));

  // Written again: TetGen's node columns, in TetGen's order.
  io::write_mesh(m, (dir / "again.node").string());
  const auto theirs = tetgen_rows((dir / "box.1.ele").string());
  const auto ours = tetgen_rows((dir / "again.ele").string());
  ASSERT_EQ(theirs.size(), ours.size());
  for (size_t i = 0; i < theirs.size(); ++i) {
    ASSERT_GE(theirs[i].size(), 11u);
    ASSERT_GE(ours[i].size(), 11u);
    EXPECT_EQ(std::vector<std::string>(theirs[i].begin() + 1, theirs[i].begin() + 11),
              std::vector<std::string>(ours[i].begin() + 1, ours[i].begin() + 11))
        << "tetrahedron " << i;
  }
  const auto their_faces = tetgen_rows((dir / "box.1.face").string());
  const auto our_faces = tetgen_rows((dir / "again.face").string());
  ASSERT_EQ(their_faces.size(), our_faces.size());
  for (size_t i = 0; i < their_faces.size(); ++i) EXPECT_EQ(their_faces[i], our_faces[i]) << "face " << i;
}

TEST(ConvertersRoundTrip, TetgenFaceLayoutsByFieldCount) {
  const std::string base = test::temp_path("layouts");
  std::ofstream(base + ".node") << "7 3 0 0\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 .5 0 0\n5 .5 .5 0\n6 0 .5 0\n7 0 0 1\n";
  // Linear with adjacent tetrahedra (-nn), then second order without marker.
  std::ofstream(base + ".face") << "1 1\n1 1 2 3 5 -1 -1\n";
  Mesh m = io::read_mesh(base + ".node");
  ASSERT_EQ(m.triangles.size(), 1u);
  EXPECT_EQ(m.triangles[0].face, 5);
  EXPECT_TRUE(m.triangle_mid.empty());
  std::ofstream(base + ".face") << "1 0\n1 1 2 3 4 5 6\n";
  m = io::read_mesh(base + ".node");
  ASSERT_EQ(m.triangle_mid.size(), 1u);
  EXPECT_EQ(m.triangle_mid[0], (TriMidNodes{3, 4, 5}));
  // Four fields with a marker flag fit neither layout.
  std::ofstream(base + ".face") << "1 1\n1 1 2 3 4 5\n";
  try {
    io::read_mesh(base + ".node");
    ADD_FAILURE() << "a face line of 5 fields after the number was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("layouts.face:2:"), std::string::npos) << e.what();
  }
}

// Surfaces: a subdivided box (6 faces) and an icosphere.
Mesh tagged_surface() {
  Mesh m = shapes::box({-1.25, 0.5, 3}, {2.5, 1.75, 4.125}, 2);
  shapes::append(m, shapes::icosphere({5, 5, 5}, 0.7, 1, 2, 7));
  return m;
}

struct SurfaceVariant {
  std::string file;
  bool binary = false;
  bool faces = true;  // face ids come back
  bool sides = false;  // front/back come back
  bool exact = true;   // coordinates exact (binary STL is float)
  bool welds = false;  // the reader merges equal points (STL)
};

TEST(ConvertersRoundTrip, SurfaceFormats) {
  const Mesh m = tagged_surface();
  const std::vector<SurfaceVariant> variants = {
      {"s.off", false, false},          {"s.obj"},
      {"s.stl", false, true, false, true, true}, {"s.stl", true, false, false, false, true},
      {"s.smesh"},                      {"s.poly"},
      {"s.mesh"},                       {"s.msh", false, true, true},
      {"s.msh", true, true, true},      {"s.vtu", true, true, true},
      {"s.vtk", false, true, true},     {"s.inp"},
      {"s.off.gz", false, false},       {"s.face"},
      {"s.ply", false, true, true},     {"s.ply", true, true, true},
  };
  for (const SurfaceVariant& v : variants) {
    SCOPED_TRACE(v.file + (v.binary ? " binary" : ""));
    const std::string path = test::temp_path((v.binary ? "b" : "a") + v.file);
    io::WriteOptions options;
    options.binary = v.binary;
    io::write_mesh(m, path, options);
    const Mesh back = io::read_mesh(path);
    ASSERT_EQ(back.points.size(), m.points.size());
    ASSERT_EQ(back.triangles.size(), m.triangles.size());
    EXPECT_TRUE(back.tets.empty());
    auto same_point = [&](const Vec3& a, const Vec3& b) {
      if (v.exact) return a.x == b.x && a.y == b.y && a.z == b.z;
      return b.x == double(float(a.x)) && b.y == double(float(a.y)) && b.z == double(float(a.z));
    };
    if (!v.welds)
      for (size_t i = 0; i < m.points.size(); ++i) EXPECT_TRUE(same_point(m.points[i], back.points[i])) << "point " << i;
    for (size_t i = 0; i < m.triangles.size(); ++i) {
      const Triangle& a = m.triangles[i];
      const Triangle& b = back.triangles[i];
      if (v.welds) {
        // Points are renumbered by welding: compare the corners' coordinates.
        for (int k = 0; k < 3; ++k) EXPECT_TRUE(same_point(m.points[a.v[k]], back.points[b.v[k]])) << "triangle " << i;
      } else {
        EXPECT_EQ(rotated(a.v), rotated(b.v)) << "triangle " << i;
      }
      EXPECT_EQ(b.face, v.faces ? a.face : kNoFace) << "triangle " << i;
      if (v.sides) {
        EXPECT_EQ(b.front, a.front) << "triangle " << i;
        EXPECT_EQ(b.back, a.back) << "triangle " << i;
      }
    }
  }
}

// A surface whose tags say the sides (a CAD tessellation keeps each face's
// own orientation) written where nothing can say them: each facet turned so
// that its normal points into the lower-numbered region, out of the solids,
// and the file reads back as a closed, consistently oriented surface.
// An ASCII STL starts a solid each time the face changes in facet order; a
// name seen again is the same face (11 faces came back as 195).
TEST(ConvertersRoundTrip, AsciiStlSolidsOfOneNameAreOneFace) {
  Mesh m = cube_tets();
  m.tets.clear();
  m.tet_mid.clear();
  ASSERT_GE(m.triangles.size(), 6u);
  std::vector<int> faces;
  for (size_t i = 0; i < m.triangles.size(); ++i) {
    m.triangles[i].face = i % 2 == 0 ? 3 : 7;  // alternating: a solid per facet
    faces.push_back(m.triangles[i].face);
  }
  for (const bool named : {false, true}) {
    m.face_names.clear();
    if (named) m.face_names = {{3, "top"}, {7, "rest"}};
    const std::string path = test::temp_path(named ? "named.stl" : "faces.stl");
    io::write_mesh(m, path);
    const Mesh back = io::read_mesh(path);
    ASSERT_EQ(back.triangles.size(), m.triangles.size());
    std::set<int> ids;
    for (size_t i = 0; i < back.triangles.size(); ++i) {
      ids.insert(back.triangles[i].face);
      if (!named) EXPECT_EQ(back.triangles[i].face, faces[i]);
      else EXPECT_EQ(back.face_names.at(back.triangles[i].face), faces[i] == 3 ? "top" : "rest");
    }
    EXPECT_EQ(ids.size(), 2u);
  }
}

TEST(ConvertersRoundTrip, FormatsWithoutSidesTurnFacetsOutOfTheirRegion) {
  Mesh outward = tagged_surface();
  Mesh m = outward;
  int turned = 0;
  for (size_t i = 0; i < m.triangles.size(); i += 2) {
    Triangle& t = m.triangles[i];
    ASSERT_EQ(t.front, 0);
    std::swap(t.v[1], t.v[2]);
    std::swap(t.front, t.back);
    ++turned;
  }
  ASSERT_GT(turned, 20);
  auto normal = [](const Mesh& mesh, const Triangle& t) {
    const Vec3 a = mesh.points[t.v[0]];
    return cross(mesh.points[t.v[1]] - a, mesh.points[t.v[2]] - a);
  };
  for (const auto& [file, binary, msh_version] : std::vector<std::tuple<std::string, bool, int>>{
           {"t.off", false, 41}, {"t.obj", false, 41}, {"t.stl", false, 41}, {"t.stl", true, 41}, {"t.mesh", false, 41},
           {"t.msh", false, 22}, {"t.msh", true, 22}, {"t.face", false, 41}, {"t.smesh", false, 41},
           {"t.inp", false, 41}}) {
    SCOPED_TRACE(file + (binary ? " binary" : "") + " msh " + std::to_string(msh_version));
    const std::string path = test::temp_path((binary ? "b" : "a") + file);
    io::WriteOptions options;
    options.binary = binary;
    options.msh_version = msh_version;
    io::write_mesh(m, path, options);
    const Mesh back = io::read_mesh(path);
    ASSERT_EQ(back.triangles.size(), outward.triangles.size());
    for (size_t i = 0; i < back.triangles.size(); ++i)
      EXPECT_GT(dot(normal(back, back.triangles[i]), normal(outward, outward.triangles[i])), 0) << "triangle " << i;
  }
  // An interface facet (regions 1 and 2) points into region 1.
  Mesh two = cube_tets();
  two.tets.clear();
  const auto interface = std::find_if(two.triangles.begin(), two.triangles.end(),
                                      [](const Triangle& t) { return t.front == 2 && t.back == 1; });
  ASSERT_NE(interface, two.triangles.end());
  const std::string path = test::temp_path("interface.off");
  io::write_mesh(two, path);
  const Mesh back = io::read_mesh(path);
  const size_t i = static_cast<size_t>(interface - two.triangles.begin());
  EXPECT_LT(dot(normal(back, back.triangles[i]), normal(two, *interface)), 0);
}

// Counts from /work/shared/data/MANIFEST.tsv.
struct SharedSurface {
  const char* file;
  size_t vertices, facets;
};

TEST(ConvertersRoundTrip, ReadsSharedSurfaces) {
  const SharedSurface files[] = {
      {"surface/cgal_fandisk.off", 6475, 12946},     {"surface/netgen_part1.stl", 190, 380},
      {"surface/meshlab_casting.off", 5096, 10224},  {"surface/cgal_anchor_dense.off", 3793, 7598},
      {"surface/cgal_turbine.off", 9210, 18460},     {"surface/cgal_cheese.off", 8629, 17786},
      {"surface/gmsh_lever.stl", 377, 774},          {"surface/cgal_bunny00.off", 37706, 75408},
      {"surface/cgal_armadillo.off", 26002, 52000},  {"surface/c3tm_rocker-arm.obj", 10044, 20088},
      {"surface/cgal_triceratops.off", 2832, 5660},
      {"surface-multiregion/cgal_complex_merged.off", 1599, 3310},
      {"surface-multiregion/cgal_horizons.off", 1682, 3200},
  };
  for (const SharedSurface& f : files) {
    SCOPED_TRACE(f.file);
    const std::string path = test::data_file(f.file);
    if (path.empty()) GTEST_SKIP() << "shared data not found: " << f.file << " (set VDMESH_DATA)";
    const Mesh m = io::read_mesh(path);
    EXPECT_EQ(m.points.size(), f.vertices);
    EXPECT_EQ(m.triangles.size(), f.facets);
    // Closed surfaces: every edge is used an even number of times.
    std::map<std::pair<int, int>, int> edges;
    for (const Triangle& t : m.triangles)
      for (int k = 0; k < 3; ++k) edges[std::minmax(t.v[k], t.v[(k + 1) % 3])]++;
    // Surfaces of the multi-region set may be open or non-manifold.
    if (std::string(f.file).rfind("surface/", 0) == 0)
      for (const auto& [e, n] : edges) ASSERT_EQ(n % 2, 0) << "edge " << e.first << "-" << e.second;
  }
}

TEST(ConvertersRoundTrip, ReadsSharedGzippedObj) {
  VD_REQUIRE_DATA(path, "surface-large/openfoam_buildings.obj.gz");
  const Mesh m = io::read_mesh(path);
  EXPECT_EQ(m.points.size(), 200062u);
  EXPECT_EQ(m.triangles.size(), 400020u);
}

// PLC files: polygons triangulated; a quad facet gives 2 triangles, a facet
// with k vertices k-2 (no holes); the area of each facet is kept.
double area(const Mesh& m, const Triangle& t) {
  return 0.5 * norm(cross(m.points[t.v[1]] - m.points[t.v[0]], m.points[t.v[2]] - m.points[t.v[0]]));
}

// A PLC facet is triangulated Delaunay in its plane (its polygons' edges
// kept): ear clipping alone left a fan of needles here, whose coplanar pairs
// recovery without flips could never make Delaunay.
TEST(ConvertersRoundTrip, PlcPolygonIsTriangulatedDelaunayInItsPlane) {
  // A 10 x 1 rectangle with 9 more points on its bottom side, in the plane
  // z = 2 and tilted by 44 deg about the x axis: projected by dropping z, a
  // tilted facet's circles are ellipses, and flips by the projection's
  // circles left pairs that are not Delaunay in the facet's plane.
  for (const double tilt : {0.0, 44.0}) {
    SCOPED_TRACE(tilt);
    const double c = std::cos(tilt * M_PI / 180), s = std::sin(tilt * M_PI / 180);
    const Vec3 normal{0, -s, c};
    auto place = [&](double x, double y) { return Vec3{x, y * c, 2 + y * s}; };
    std::vector<Vec3> points;
    std::vector<int> polygon;
    for (int i = 0; i <= 10; ++i) {
      polygon.push_back(static_cast<int>(points.size()));
      points.push_back(place(i, 0));
    }
    for (const Vec3& p : {place(10, 1), place(0, 1)}) {
      polygon.push_back(static_cast<int>(points.size()));
      points.push_back(p);
    }
    const auto tris = io::detail::triangulate_facet(points, {polygon}, {});
    ASSERT_EQ(tris.size(), points.size() - 2);
    double total = 0;
    std::map<std::pair<int, int>, int> apex;  // directed edge -> the corner off it
    for (const auto& t : tris) {
      const Vec3 n = cross(points[t[1]] - points[t[0]], points[t[2]] - points[t[0]]);
      EXPECT_GT(dot(n, normal), 0);  // turned like the polygon
      total += 0.5 * norm(n);
      for (int k = 0; k < 3; ++k) apex[{t[k], t[(k + 1) % 3]}] = t[(k + 2) % 3];
    }
    EXPECT_NEAR(total, 10.0, 1e-12);
    // No corner across an inner edge lies inside the other triangle's circle.
    int inner = 0;
    for (const auto& t : tris)
      for (int k = 0; k < 3; ++k) {
        const auto across = apex.find({t[(k + 1) % 3], t[k]});
        if (across == apex.end()) continue;
        ++inner;
        EXPECT_NE(side_of_equatorial_sphere(points[t[0]], points[t[1]], points[t[2]], points[across->second]),
                  SphereSide::inside)
            << "edge " << t[k] << "-" << t[(k + 1) % 3];
      }
    EXPECT_EQ(inner, 2 * (static_cast<int>(tris.size()) - 1));
  }
}

TEST(ConvertersRoundTrip, ReadsSharedSmesh) {
  // V, facets, triangles after ear clipping (sum of k-2 over the facets).
  const struct {
    const char* file;
    size_t vertices, facets, triangles;
  } files[] = {{"plc-sharp/testingdrafts_wedge-1.smesh", 6, 5, 8},
               {"plc-sharp/testingdrafts_slit-1.smesh", 14, 13, 24},
               {"plc-sharp/testingdrafts_spike-1-10.smesh", 11, 11, 18}};
  for (const auto& f : files) {
    SCOPED_TRACE(f.file);
    const std::string path = test::data_file(f.file);
    if (path.empty()) GTEST_SKIP() << "shared data not found: " << f.file;
    const Mesh m = io::read_mesh(path);
    EXPECT_EQ(m.points.size(), f.vertices);
    EXPECT_EQ(m.triangles.size(), f.triangles);
    std::set<int> faces;
    for (const Triangle& t : m.triangles) {
      faces.insert(t.face);
      EXPECT_GT(area(m, t), 0);
    }
    EXPECT_LE(faces.size(), f.facets);
    // Closed: every edge twice.
    std::map<std::pair<int, int>, int> edges;
    for (const Triangle& t : m.triangles)
      for (int k = 0; k < 3; ++k) edges[std::minmax(t.v[k], t.v[(k + 1) % 3])]++;
    for (const auto& [e, n] : edges) EXPECT_EQ(n, 2) << "edge " << e.first << "-" << e.second;
  }
}

// An L-shaped prism whose caps are single non-convex hexagons, as OFF, OBJ
// and .smesh: each cap must be covered once (area 3, enclosed volume 3).
// The fan of OFF and OBJ folded the caps (area 4), and the facet
// triangulation of .poly/.smesh let an ear reach outside the L through a
// reflex corner on its diagonal, until 2026-11-30.
TEST(ConvertersRoundTrip, NonConvexPolygonsAreTriangulatedInside) {
  const char* points = "0 0 0\n2 0 0\n2 1 0\n1 1 0\n1 2 0\n0 2 0\n0 0 1\n2 0 1\n2 1 1\n1 1 1\n1 2 1\n0 2 1\n";
  // 0-based; the bottom turned down, the top up, the sides out.
  const std::vector<std::vector<int>> faces = {{5, 4, 3, 2, 1, 0}, {6, 7, 8, 9, 10, 11}, {0, 1, 7, 6}, {1, 2, 8, 7},
                                               {2, 3, 9, 8},       {3, 4, 10, 9},        {4, 5, 11, 10}, {5, 0, 6, 11}};
  std::string off = std::string("OFF\n12 8 0\n") + points, obj, smesh = "12 3 0 0\n";
  std::string vtk = std::string("# vtk DataFile Version 3.0\nx\nASCII\nDATASET POLYDATA\nPOINTS 12 double\n") + points +
                    "POLYGONS 8 44\n";
  std::string ply = std::string("ply\nformat ascii 1.0\nelement vertex 12\nproperty double x\nproperty double y\n"
                                "property double z\nelement face 8\nproperty list uchar int vertex_indices\n"
                                "end_header\n") + points;
  std::istringstream lines(points);
  int k = 0;
  for (std::string line; std::getline(lines, line);) obj += "v " + line + "\n", smesh += std::to_string(++k) + " " + line + "\n";
  smesh += "8 0\n";
  for (const auto& f : faces) {
    off += std::to_string(f.size()), obj += "f", smesh += std::to_string(f.size()), vtk += std::to_string(f.size());
    for (int v : f) {
      off += " " + std::to_string(v), obj += " " + std::to_string(v + 1), smesh += " " + std::to_string(v + 1);
      vtk += " " + std::to_string(v);
    }
    off += "\n", obj += "\n", smesh += "\n", vtk += "\n";
    ply += std::to_string(f.size());
    for (int v : f) ply += " " + std::to_string(v);
    ply += "\n";
  }
  smesh += "0\n0\n";
  for (const auto& [name, text] :
       {std::pair{"l.off", off}, std::pair{"l.obj", obj}, std::pair{"l.smesh", smesh}, std::pair{"l.vtk", vtk},
        std::pair{"l.ply", ply}}) {
    SCOPED_TRACE(name);
    const std::string path = test::temp_path(name);
    std::ofstream(path) << text;
    const Mesh m = io::read_mesh(path);
    double top = 0, bottom = 0, volume = 0;
    for (const Triangle& t : m.triangles) {
      const Vec3 a = m.points[t.v[0]], b = m.points[t.v[1]], c = m.points[t.v[2]];
      const double nz = cross(b - a, c - a).z / 2;
      if (a.z == 1 && b.z == 1 && c.z == 1) top += nz;
      if (a.z == 0 && b.z == 0 && c.z == 0) bottom += nz;
      volume += dot(a, cross(b, c)) / 6;
    }
    // Every triangle of a cap turned like it: signed areas add to the cap's.
    EXPECT_DOUBLE_EQ(top, 3.0);
    EXPECT_DOUBLE_EQ(bottom, -3.0);
    EXPECT_NEAR(std::abs(volume), 3.0, 1e-12);
  }
}

// VTK POLYDATA: vertices and lines are skipped, a triangle strip is cut into
// triangles that all face as its first, and cell data (in VTK's order:
// vertices, lines, polygons, strips) goes to the triangles each cell became.
TEST(ConvertersRoundTrip, VtkPolydataStripsAndCellData) {
  const std::string path = test::temp_path("strips.vtk");
  std::ofstream(path) << "# vtk DataFile Version 3.0\nstrips\nASCII\nDATASET POLYDATA\n"
                         "POINTS 6 float\n0 0 0\n1 0 0\n0 1 0\n1 1 0\n0 2 0\n1 2 0\n"
                         "VERTICES 1 2\n1 0\nLINES 1 3\n2 0 5\nPOLYGONS 1 4\n3 2 3 4\n"
                         "TRIANGLE_STRIPS 1 7\n6 0 1 2 3 3 3\n"
                         "CELL_DATA 4\nSCALARS face int 1\nLOOKUP_TABLE default\n7 8 9 11\n";
  const Mesh m = io::read_mesh(path);
  ASSERT_EQ(m.triangles.size(), 3u);  // the polygon, then the strip's two (its degenerate ones dropped)
  EXPECT_EQ(m.triangles[0].face, 9);
  EXPECT_EQ(m.triangles[1].face, 11);
  EXPECT_EQ(m.triangles[2].face, 11);
  for (const Triangle& t : m.triangles) {
    const Vec3 a = m.points[t.v[0]], b = m.points[t.v[1]], c = m.points[t.v[2]];
    EXPECT_DOUBLE_EQ(cross(b - a, c - a).z, 1.0) << t.v[0] << " " << t.v[1] << " " << t.v[2];
  }
}

// PLY's tristrips element (old scanner files): one list of strips, -1
// between them, the same strip rule as VTK's. A unit cube, a strip a side
// (a, b, d, c for the side a b c d), one side as two strips joined by a
// degenerate triangle: 12 triangles, every edge in two of them, volume 1.
// A list of unsigned ints writes -1 as 4294967295.
TEST(ConvertersRoundTrip, PlyTriangleStrips) {
  for (const std::string end : {"-1", "4294967295"}) {
    const std::string path = test::temp_path("strips.ply");
    std::ofstream(path) << "ply\nformat ascii 1.0\ncomment strips\nelement vertex 8\nproperty float x\n"
                           "property float y\nproperty float z\nelement tristrips 1\n"
                           "property list int " << (end == "-1" ? "int" : "uint") << " vertex_indices\nend_header\n"
                           "0 0 0\n1 0 0\n1 1 0\n0 1 0\n0 0 1\n1 0 1\n1 1 1\n0 1 1\n"
                           "30 0 3 1 2 " << end << " 4 5 7 6 " << end << " 0 1 4 5 " << end << " 3 7 2 6 " << end
                        << " 0 4 3 7 7 1 1 2 5 6\n";
    SCOPED_TRACE(end);
    const Mesh m = io::read_mesh(path);
    ASSERT_EQ(m.triangles.size(), 12u);
    double volume = 0;
    std::map<std::pair<int, int>, int> directed;
    for (const Triangle& t : m.triangles) {
      volume += dot(m.points[t.v[0]], cross(m.points[t.v[1]], m.points[t.v[2]])) / 6;
      for (int k = 0; k < 3; ++k) ++directed[{t.v[k], t.v[(k + 1) % 3]}];
    }
    EXPECT_DOUBLE_EQ(volume, 1.0);
    // Closed and oriented alike: each directed edge once, and its reverse once.
    for (const auto& [edge, count] : directed) {
      EXPECT_EQ(count, 1);
      EXPECT_EQ(directed.count({edge.second, edge.first}), 1u) << edge.first << " " << edge.second;
    }
  }
}

TEST(ConvertersRoundTrip, ReadsSharedPolyWithFacetHole) {
  VD_REQUIRE_DATA(path, "surface-multiregion/tetgen_example.poly");
  const Mesh m = io::read_mesh(path);
  EXPECT_EQ(m.points.size(), 28u);
  // 23 facets of quads (2 triangles each), except facet 3: a square with a
  // square hole (8 triangles around the hole).
  EXPECT_EQ(m.triangles.size(), 22u * 2 + 8);
  std::map<int, double> face_area;
  for (const Triangle& t : m.triangles) face_area[t.face] += area(m, t);
  // Markers in the file: 1, 9, 3, 2, 4.
  EXPECT_EQ(face_area.size(), 5u);
  // Facet 1 (marker 1): the 2 x 2 bottom; marker 2: the 2 x 2 top at z = 5.
  EXPECT_DOUBLE_EQ(face_area.at(1), 4.0);
  EXPECT_DOUBLE_EQ(face_area.at(2), 4.0);
  // Marker 3: the y = 0 side (2 x 4 minus the 1.5 x 0.5 hole), four more
  // sides of the lower box (2x4, 2x3, 2x3.. by the file's coordinates).
  double y0 = 0;
  for (const Triangle& t : m.triangles) {
    if (t.face != 3) continue;
    bool on_y0 = true;
    for (int v : t.v) on_y0 &= m.points[v].y == 0;
    if (on_y0 && m.points[t.v[0]].z <= 4 && m.points[t.v[1]].z <= 4 && m.points[t.v[2]].z <= 4) y0 += area(m, t);
  }
  EXPECT_DOUBLE_EQ(y0, 8.0 - 1.5 * 0.5);
  // Its hole and region lists (read past until 2026-11-30): two holes, and
  // regions 10 and 20, the ids TetGen's -A gives.
  ASSERT_EQ(m.region_points.size(), 4u);
  EXPECT_EQ(m.region_points[0].region, 0);
  EXPECT_EQ(m.region_points[1].region, 0);
  EXPECT_EQ(m.region_points[2].region, 10);
  EXPECT_EQ(m.region_points[3].region, 20);
  EXPECT_DOUBLE_EQ(m.region_points[3].at.y, 0.5);
  EXPECT_DOUBLE_EQ(m.region_points[3].at.z, 4.0);
  // Written back and read again, the same points.
  const std::string again = test::temp_path("again.poly");
  io::write_mesh(m, again);
  const Mesh back = io::read_mesh(again);
  ASSERT_EQ(back.region_points.size(), 4u);
  for (size_t i = 0; i < 4; ++i) {
    EXPECT_EQ(back.region_points[i].region, m.region_points[i].region);
    EXPECT_EQ(norm(back.region_points[i].at - m.region_points[i].at), 0.0);
  }
}

}  // namespace
}  // namespace vd
