// Medit / Gamma Mesh Format, binary (.meshb: MMG, the Gamma tools, meshio).
// A file is a word 1 (its byte order), a version, then keywords: each a
// code, the position of the next keyword, and for a table its count and
// records. Versions 1 to 4 differ in widths: reals float (1) or double,
// positions 32-bit (1, 2) or 64-bit, counts and indices 32-bit or 64-bit
// (4). Vertices, Triangles(P2), Tetrahedra(P2) are read as in .mesh
// (references: face ids and regions, 0 none on a tetrahedron; second order
// as in .mesh, medit.cpp); keywords vdmesh has no use for are
// stepped over by their position, elements it has no place for refused.
// Written as version 2 (doubles, 32-bit words) below 2 GiB, else 3.
#include <algorithm>
#include <array>
#include <cstdint>
#include <cstring>
#include <climits>
#include <map>
#include <string>
#include <tuple>
#include <vector>

#include "formats.h"
#include "io_util.h"
#include "mesh/error.h"

namespace vd::io {
namespace {

// The keyword codes of libMeshb's table vdmesh reads.
enum Keyword : int32_t {
  kDimension = 3,
  kVertices = 4,
  kTriangles = 6,
  kTetrahedra = 8,
  kTrianglesP2 = 24,
  kTetrahedraP2 = 30,
  kEnd = 54,
};

// Elements vdmesh would lose: refused when the file has any.
const std::map<int32_t, const char*>& lost_keywords() {
  static const std::map<int32_t, const char*> lost = {
      {7, "quadrilaterals"}, {9, "prisms"},     {10, "hexahedra"},   {27, "second-order quadrilaterals"},
      {33, "second-order hexahedra"}, {46, "polyhedra"}, {49, "pyramids"},
      // libMeshb 7's higher orders (skipped until 2026-11-30: a file of
      // third-order tetrahedra came out with none).
      {86, "second-order prisms"}, {87, "second-order pyramids"}, {88, "third-order quadrilaterals"},
      {89, "fourth-order quadrilaterals"}, {90, "third-order triangles"}, {91, "fourth-order triangles"},
      {96, "third-order tetrahedra"}, {97, "fourth-order tetrahedra"}, {98, "third-order hexahedra"},
      {99, "fourth-order hexahedra"}, {100, "third-order pyramids"}, {101, "fourth-order pyramids"},
      {102, "third-order prisms"}, {103, "fourth-order prisms"}, {47, "polygons"}, {200, "9-node prisms"},
      {201, "12-node hexahedra"}, {202, "6-node quadrilaterals"}};
  return lost;
}

class MeshbReader {
 public:
  MeshbReader(std::string_view d, const std::string& path) : d_(d), path_(path) {}
  Mesh read();

 private:
  [[noreturn]] void fail(size_t at, const std::string& what) const {
    throw InputError(path_ + ": byte " + std::to_string(at) + ": " + what);
  }
  // An unsigned word of `size` bytes at pos_, in the file's byte order.
  uint64_t word(size_t size, const char* what) {
    if (size > d_.size() - pos_) fail(pos_, std::string("the file ends inside ") + what);
    unsigned char b[8];
    std::memcpy(b, d_.data() + pos_, size);
    pos_ += size;
    uint64_t v = 0;
    for (size_t i = 0; i < size; ++i) v |= uint64_t{b[swap_ ? size - 1 - i : i]} << (8 * i);
    return v;
  }
  int64_t integer(size_t size, const char* what) {
    const uint64_t v = word(size, what);
    return size == 4 ? static_cast<int64_t>(static_cast<int32_t>(v)) : static_cast<int64_t>(v);
  }
  double real(const char* what) {
    const uint64_t v = word(real_size_, what);
    if (real_size_ == 4) {
      float f;
      const uint32_t w = static_cast<uint32_t>(v);
      std::memcpy(&f, &w, 4);
      return f;
    }
    double r;
    std::memcpy(&r, &v, 8);
    return r;
  }
  // A table's count, checked against the bytes left for its records.
  uint64_t count(size_t record_bytes, const char* what) {
    const size_t at = pos_;
    const int64_t n = integer(count_size_, "a keyword's count");
    if (n < 0 || static_cast<uint64_t>(n) > (d_.size() - pos_) / record_bytes)
      fail(at, std::string("the file is too short for its ") + std::to_string(n) + " " + what);
    return static_cast<uint64_t>(n);
  }
  int vertex(const char* what) {
    const size_t at = pos_;
    const int64_t v = integer(int_size_, what);
    if (v < 1 || static_cast<uint64_t>(v) > m_.points.size())
      fail(at, std::string(what) + " " + std::to_string(v) + " does not exist (" + std::to_string(m_.points.size()) +
                   " vertices)");
    return static_cast<int>(v - 1);
  }
  void vertices();
  template <class Element, class Mid, class TakeRef>
  void elements(std::vector<Element>& out, std::vector<Mid>& mids, bool p2, const std::string& kind, TakeRef take_ref);
  void triangles(bool p2);
  void tetrahedra(bool p2);

  std::string_view d_;
  std::string path_;
  size_t pos_ = 0;
  bool swap_ = false;
  size_t real_size_ = 8, pos_size_ = 4, count_size_ = 4, int_size_ = 4;
  Mesh m_;
};

void MeshbReader::vertices() {
  if (!m_.points.empty()) fail(pos_, "a second Vertices keyword");
  const uint64_t n = count(3 * real_size_ + int_size_, "vertices");
  if (n > INT32_MAX) fail(pos_, "more vertices than vdmesh numbers (2^31)");
  m_.points.resize(static_cast<size_t>(n));
  for (Vec3& p : m_.points) {
    p.x = real("a vertex x");
    p.y = real("a vertex y");
    p.z = real("a vertex z");
    integer(int_size_, "a vertex reference");
  }
}

// A table of triangles or tetrahedra: corners, mid-edge nodes (P2), and
// the reference `take_ref` files in the element.
template <class Element, class Mid, class TakeRef>
void MeshbReader::elements(std::vector<Element>& out, std::vector<Mid>& mids, bool p2, const std::string& kind,
                           TakeRef take_ref) {
  if (!out.empty()) fail(pos_, "a second section of " + kind + "s");
  const size_t words = std::tuple_size<decltype(Element::v)>::value + (p2 ? std::tuple_size<Mid>::value : 0) + 1;
  const uint64_t n = count(words * int_size_, (kind + "s").c_str());
  out.resize(static_cast<size_t>(n));
  if (p2) mids.resize(static_cast<size_t>(n));
  const std::string corner = "a " + kind + " vertex", mid = "a " + kind + " mid-edge node",
                    reference = "a " + kind + " reference";
  for (size_t i = 0; i < n; ++i) {
    for (int& v : out[i].v) v = vertex(corner.c_str());
    if (p2)
      for (int& v : mids[i]) v = vertex(mid.c_str());
    const int64_t ref = integer(int_size_, reference.c_str());
    if (ref < INT32_MIN || ref > INT32_MAX) fail(pos_, reference + " beyond 32 bits");
    take_ref(out[i], static_cast<int>(ref));
  }
}

void MeshbReader::triangles(bool p2) {
  elements(m_.triangles, m_.triangle_mid, p2, "triangle", [](Triangle& t, int ref) { t.face = ref; });
}

void MeshbReader::tetrahedra(bool p2) {
  // Reference 0 is no region, as in .mesh.
  elements(m_.tets, m_.tet_mid, p2, "tetrahedron",
           [](Tetrahedron& t, int ref) { t.region = ref == 0 ? kUnknownRegion : ref; });
}

Mesh MeshbReader::read() {
  if (d_.size() < 8) fail(0, "too short for a .meshb file");
  const uint64_t first = word(4, "the byte-order word");
  if (first == 0x01000000u) swap_ = true;
  else if (first != 1) fail(0, "not a binary Medit file (its first word is " + std::to_string(first) + ", not 1)");
  const int64_t version = integer(4, "the version");
  if (version < 1 || version > 4) fail(4, "unknown .meshb version " + std::to_string(version) + " (1 to 4 are read)");
  real_size_ = version == 1 ? 4 : 8;
  pos_size_ = version >= 3 ? 8 : 4;
  count_size_ = int_size_ = version == 4 ? 8 : 4;
  // Keywords in turn, each found at the position the last one gave; a
  // position that does not move forward ends a broken file rather than loop.
  // The element keywords are read after the walk: a file may list them
  // before its Vertices.
  struct Table {
    int64_t code;
    size_t at, body, next;
  };
  std::vector<Table> tables;
  while (pos_ < d_.size()) {
    const size_t at = pos_;
    const int64_t code = integer(4, "a keyword code");
    const uint64_t next = word(pos_size_, "a keyword's next position");
    if (code == kEnd) break;
    if (code == kDimension) {
      const int64_t dim = integer(4, "the dimension");
      if (dim != 3) fail(at, "only 3D meshes are supported (Dimension " + std::to_string(dim) + ")");
    } else if (code == kVertices || code == kTriangles || code == kTrianglesP2 || code == kTetrahedra ||
               code == kTetrahedraP2) {
      tables.push_back({code, at, pos_, static_cast<size_t>(std::min<uint64_t>(next, d_.size()))});
    } else if (const auto lost = lost_keywords().find(static_cast<int32_t>(code)); lost != lost_keywords().end()) {
      const int64_t n = integer(count_size_, "a keyword's count");
      if (n != 0)
        fail(at, std::to_string(n) + " " + lost->second + ": vdmesh reads triangles and tetrahedra only, and would lose them");
    }
    if (next == 0) break;  // the last keyword
    if (next <= at || next > d_.size()) fail(at, "keyword " + std::to_string(code) + " gives " + std::to_string(next) +
                                                     " as the next keyword's position");
    pos_ = static_cast<size_t>(next);
  }
  std::stable_partition(tables.begin(), tables.end(), [](const Table& t) { return t.code == kVertices; });
  for (const Table& t : tables) {
    pos_ = t.body;
    if (t.code == kVertices) vertices();
    else if (t.code == kTriangles || t.code == kTrianglesP2) triangles(t.code == kTrianglesP2);
    else tetrahedra(t.code == kTetrahedraP2);
    // A table read in full ends where the next keyword begins (libMeshb
    // writes no gap): anything else is a record layout vdmesh misread.
    if (t.next != 0 && t.next != pos_)
      fail(t.at, "keyword " + std::to_string(t.code) + " ends at byte " + std::to_string(pos_) +
                     ", but the next keyword is at " + std::to_string(t.next));
  }
  detail::require_valid(m_, path_);
  detail::sides_from_tets(m_);
  return std::move(m_);
}

Mesh read_meshb(const std::string& path) {
  const detail::FileBytes data(path);
  return MeshbReader(data.view(), path).read();
}

// Words of the version written: 32-bit (2) or, for a file of 2 GiB or more,
// 64-bit positions (3).
class MeshbWriter {
 public:
  MeshbWriter(detail::Out& out, int version) : out_(out), pos_size_(version >= 3 ? 8 : 4) {
    put32(1);
    put32(version);
  }
  void put32(int64_t v) {
    out_.raw(static_cast<int32_t>(v));
    at_ += 4;
  }
  void put_real(double v) {
    out_.raw(v);
    at_ += 8;
  }
  // A keyword whose body is `body_bytes` long: its code and the next one's position.
  void keyword(int32_t code, uint64_t body_bytes) {
    put32(code);
    const uint64_t next = code == kEnd ? 0 : at_ + pos_size_ + body_bytes;
    if (pos_size_ == 8) out_.raw(next);
    else out_.raw(static_cast<uint32_t>(next));
    at_ += pos_size_;
  }

 private:
  detail::Out& out_;
  size_t pos_size_;
  uint64_t at_ = 0;
};

void write_meshb(const Mesh& m, const std::string& path, const WriteOptions&) {
  const bool tri_p2 = !m.triangle_mid.empty(), tet_p2 = !m.tet_mid.empty();
  const uint64_t bytes = 64 + m.points.size() * 28 + m.triangles.size() * (tri_p2 ? 28 : 16) +
                         m.tets.size() * (tet_p2 ? 44 : 20);
  const int version = bytes < (uint64_t{1} << 31) ? 2 : 3;
  // Counts and indices are 32-bit words in both.
  if (m.triangles.size() > INT32_MAX || m.tets.size() > INT32_MAX)
    throw InputError(path + ": more than 2^31 elements, which .meshb versions 2 and 3 cannot count");
  detail::Out out(path);
  MeshbWriter w(out, version);
  w.keyword(kDimension, 4);
  w.put32(3);
  w.keyword(kVertices, 4 + m.points.size() * 28);
  w.put32(static_cast<int64_t>(m.points.size()));
  for (const Vec3& p : m.points) {
    w.put_real(p.x);
    w.put_real(p.y);
    w.put_real(p.z);
    w.put32(0);
  }
  if (!m.triangles.empty()) {
    w.keyword(tri_p2 ? kTrianglesP2 : kTriangles, 4 + m.triangles.size() * (tri_p2 ? 28 : 16));
    w.put32(static_cast<int64_t>(m.triangles.size()));
    for (size_t i = 0; i < m.triangles.size(); ++i) {
      const Triangle& t = m.triangles[i];
      // Without tetrahedra nothing says a triangle's sides (as in .mesh).
      const std::array<int, 3> v = m.tets.empty() ? detail::corners_without_sides(t) : t.v;
      for (int x : v) w.put32(x + 1);
      if (tri_p2) {
        const TriMidNodes x = m.tets.empty() ? detail::mid_nodes_without_sides(t, m.triangle_mid[i]) : m.triangle_mid[i];
        for (int y : x) w.put32(y + 1);
      }
      w.put32(std::max(t.face, 0));  // reference 0: none, as in .mesh
    }
  }
  if (!m.tets.empty()) {
    w.keyword(tet_p2 ? kTetrahedraP2 : kTetrahedra, 4 + m.tets.size() * (tet_p2 ? 44 : 20));
    w.put32(static_cast<int64_t>(m.tets.size()));
    for (size_t i = 0; i < m.tets.size(); ++i) {
      for (int x : m.tets[i].v) w.put32(x + 1);
      if (tet_p2)
        for (int y : m.tet_mid[i]) w.put32(y + 1);
      w.put32(std::max(m.tets[i].region, 0));
    }
  }
  w.keyword(kEnd, 0);
  out.finish();
}

}  // namespace

Format make_meshb_format() { return {"meshb", {".meshb"}, true, read_meshb, write_meshb, {}}; }

}  // namespace vd::io
