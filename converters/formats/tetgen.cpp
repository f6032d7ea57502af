// TetGen's mesh files: X.node (points), X.ele (tetrahedra, the first
// attribute is the region), X.face (triangles, the marker is the face id).
// Any of them, or the base X, names the set; reading takes the ones present.
// Numbering starts at 0 or 1, as the first node says. Second order (`tetgen
// -o2`): ten-node tetrahedra and six-node faces, read and written.
//
// TetGen 1.5.0 (Debian 12's) orders a tetrahedron's mid-edge nodes on the
// edges (23, 03, 01, 12, 13, 02), checked against `tetgen -pq1.4o2` output
// (tests/unit/converters_roundtrip_test.cpp runs it); a face's on (01, 12, 20),
// as vdmesh. The .face file does not say how many nodes a face has, so the
// number of fields on its first line does (see face_layout).
#include <algorithm>
#include <array>
#include <cstdio>
#include <cstdint>
#include <filesystem>
#include <string_view>

#include "formats.h"
#include "io_util.h"
#include "tetgen_files.h"

namespace vd::io {
namespace detail {

std::string tetgen_base(const std::string& path) {
  const std::string ext = extension_of(path);
  if (ext == ".node" || ext == ".ele" || ext == ".face" || ext == ".poly" || ext == ".smesh")
    return strip_extension(path);
  return path;
}

int read_tetgen_nodes(Cursor& in, Mesh& m) {
  const uint64_t n = in.count("the number of nodes", INT32_MAX);
  const int64_t dim = in.integer("the dimension");
  if (dim != 3) in.fail("only 3D node files are supported (dimension " + std::to_string(dim) + ")");
  in.count("the number of attributes");
  in.count("the boundary marker flag");
  m.points.reserve(capped(n, in.remaining(), 8));
  int first = 0;
  for (uint64_t i = 0; i < n; ++i) {
    const int64_t id = in.integer("a node number");
    if (i == 0) {
      if (id != 0 && id != 1) in.fail("the first node must be numbered 0 or 1, not " + std::to_string(id));
      first = static_cast<int>(id);
    }
    if (id != first + static_cast<int64_t>(i))
      in.fail("node numbers must be consecutive: expected " + std::to_string(first + i) + ", found " +
              std::to_string(id));
    Vec3 p;
    p.x = in.real("a node x");
    p.y = in.real("a node y");
    p.z = in.real("a node z");
    m.points.push_back(p);
    in.skip_line();  // attributes, marker
  }
  return first;
}

int tetgen_vertex(Cursor& in, const Mesh& m, int first, const char* what) {
  const int64_t id = in.integer(what);
  if (id < first || static_cast<uint64_t>(id - first) >= m.points.size())
    in.fail(std::string(what) + " " + std::to_string(id) + " does not exist");
  return static_cast<int>(id - first);
}

}  // namespace detail

namespace {

using detail::Cursor;

// kTetgenMid[k]: the position in TetMidNodes (01, 12, 20, 03, 13, 23) of the
// k-th mid node TetGen writes.
constexpr int kTetgenMid[6] = {5, 3, 0, 1, 4, 2};

void read_ele(const std::string& path, Mesh& m, int first) {
  const detail::FileBytes data(path);
  Cursor in(data, path);
  in.set_comment('#');
  const uint64_t n = in.count("the number of tetrahedra", data.size());
  const int64_t k = in.integer("the nodes per tetrahedron");
  if (k != 4 && k != 10) in.fail("tetrahedra must have 4 or 10 nodes, not " + std::to_string(k));
  const uint64_t nattr = in.count("the number of attributes", 1 << 20);
  m.tets.reserve(detail::capped(n, data.size(), 10));
  for (uint64_t i = 0; i < n; ++i) {
    in.integer("a tetrahedron number");
    Tetrahedron t;
    for (int& v : t.v) v = detail::tetgen_vertex(in, m, first, "a tetrahedron node");
    if (k == 10) {
      TetMidNodes mid;
      for (int j : kTetgenMid) mid[j] = detail::tetgen_vertex(in, m, first, "a tetrahedron mid node");
      m.tet_mid.push_back(mid);
    }
    if (nattr > 0) {
      const double a = in.real("a region attribute");
      if (a < -2e9 || a > 2e9) in.fail("region attribute out of range");
      t.region = static_cast<int>(a);
    }
    m.tets.push_back(t);
    in.skip_line();
  }
}

// A face line is: number, 3 or 6 nodes, the marker when the header says so,
// and 2 adjacent tetrahedra with `-nn`. Without the marker the counts after
// the number are 3, 5 (linear) or 6, 8 (second order); with it one more: no
// count is ambiguous. Returns the nodes per face.
int face_layout(size_t fields_after_number, bool markers, const Cursor& in) {
  const size_t marker_fields = markers ? 1 : 0;
  if (fields_after_number >= marker_fields) {
    const size_t nodes_and_adjacent = fields_after_number - marker_fields;
    if (nodes_and_adjacent == 3 || nodes_and_adjacent == 5) return 3;
    if (nodes_and_adjacent == 6 || nodes_and_adjacent == 8) return 6;
  }
  in.fail("a face line needs 3 or 6 nodes" + std::string(markers ? ", a marker" : "") +
          " and optionally 2 adjacent tetrahedra, not " + std::to_string(fields_after_number) + " fields");
}

int face_vertex(const Cursor& in, std::string_view field, const Mesh& m, int first) {
  int64_t id = 0;
  if (!Cursor::parse_int(field, id))
    in.fail("expected a face node (an integer), found '" + std::string(field.substr(0, 40)) + "'");
  if (id < first || static_cast<uint64_t>(id - first) >= m.points.size())
    in.fail("a face node " + std::to_string(id) + " does not exist");
  return static_cast<int>(id - first);
}

// Returns whether the faces have markers.
bool read_face(const std::string& path, Mesh& m, int first) {
  const detail::FileBytes data(path);
  Cursor in(data, path);
  in.set_comment('#');
  const uint64_t n = in.count("the number of faces", data.size());
  const bool markers = in.count("the boundary marker flag") != 0;
  m.triangles.reserve(detail::capped(n, data.size(), 8));
  int nodes = 0;
  for (uint64_t i = 0; i < n; ++i) {
    in.integer("a face number");
    std::array<std::string_view, 9> field;
    size_t count = 0;
    while (in.line_has_more()) {
      if (count == field.size()) in.fail("too many fields on a face line");
      field[count++] = in.token_in_line();
    }
    const int layout = face_layout(count, markers, in);
    if (i == 0) nodes = layout;
    if (layout != nodes)
      in.fail("this face has " + std::to_string(layout) + " nodes, the first one " + std::to_string(nodes));
    Triangle t;
    for (int k = 0; k < 3; ++k) t.v[k] = face_vertex(in, field[k], m, first);
    if (nodes == 6) {
      TriMidNodes mid;
      for (int k = 0; k < 3; ++k) mid[k] = face_vertex(in, field[3 + k], m, first);
      m.triangle_mid.push_back(mid);
    }
    if (markers) {
      int64_t marker = 0;
      if (!Cursor::parse_int(field[nodes], marker) || marker < INT32_MIN || marker > INT32_MAX)
        in.fail("expected a face marker (a 32-bit integer), found '" + std::string(field[nodes].substr(0, 40)) + "'");
      t.face = static_cast<int>(marker);
    }
    m.triangles.push_back(t);
    in.skip_line();
  }
  return markers;
}

bool exists(const std::string& p) {
  std::error_code ec;
  return std::filesystem::exists(p, ec);
}

// `tetgen -f` lists every face of the mesh, the inner ones with marker 0:
// those with one region on both sides (or tetrahedra without regions, no
// `-A`, on both) are no boundary (they were read as a face "Face0" of 1,437
// triangles of a 1,943-face file, and MSH 4.1 written from it did not open
// in meshio). A face with a marker, or between two regions, stays (an
// interface, or a sheet inside a region).
void drop_inner_faces(Mesh& m, bool markers) {
  if (m.tets.empty()) return;  // a surface alone: its sides are unknown, not inner
  detail::keep_elements_if(m.triangles, m.triangle_mid, [markers](const Triangle& t) {
    return !(t.front == t.back && t.front != 0 && (!markers || t.face == 0));
  });
}

Mesh read_tetgen(const std::string& path) {
  const std::string base = detail::tetgen_base(path);
  // One set: compressed when the path says so (or only the compressed node
  // file is there), else plain; the other kind's files are another set.
  const bool gz = detail::ends_with_ci(path, ".gz") ||
                  (!exists(base + ".node") && exists(base + ".node.gz"));
  const std::string suffix = gz ? ".gz" : "";
  const std::string node = base + ".node" + suffix;
  if (!exists(node)) throw InputError(path + ": the TetGen node file " + node + " does not exist");
  Mesh m;
  const detail::FileBytes data(node);
  Cursor in(data, node);
  in.set_comment('#');
  const int first = detail::read_tetgen_nodes(in, m);
  // A member in the other kind belongs to this set when that kind has no
  // node file, no set of its own (a .ele compressed alone was dropped).
  const std::string other = gz ? "" : ".gz";
  const bool other_set = exists(base + ".node" + other);
  const auto member = [&](const char* ext) {
    if (exists(base + ext + suffix)) return base + ext + suffix;
    if (!other_set && exists(base + ext + other)) return base + ext + other;
    return std::string();
  };
  if (const std::string ele = member(".ele"); !ele.empty()) read_ele(ele, m, first);
  bool markers = false;
  if (const std::string face = member(".face"); !face.empty()) markers = read_face(face, m, first);
  detail::require_valid(m, path);
  detail::sides_from_tets(m);
  drop_inner_faces(m, markers);
  return m;
}

// The files of the set `path` names (compressed or plain, as the path is;
// the other kind is another set, read by its own name). A write replaces
// them all: one left from an earlier mesh was read with the new ones (a
// surface written over a volume mesh came back with the old .ele, "a
// tetrahedron node 22 does not exist", or a stale tetrahedron).
std::vector<std::string> tetgen_set_files(const std::string& path) {
  const std::string base = detail::tetgen_base(path);
  const bool gz = detail::ends_with_ci(path, ".gz");
  std::vector<std::string> files;
  for (const char* ext : {".node", ".ele", ".face"}) files.push_back(base + ext + (gz ? ".gz" : ""));
  return files;
}

void write_tetgen(const Mesh& m, const std::string& path, const WriteOptions&) {
  const std::string base = detail::tetgen_base(path);
  const bool gz = detail::ends_with_ci(path, ".gz");
  const std::string suffix = gz ? ".gz" : "";
  std::vector<std::string> written = {base + ".node" + suffix};
  if (!m.tets.empty()) written.push_back(base + ".ele" + suffix);
  if (!m.triangles.empty()) written.push_back(base + ".face" + suffix);
  {
    detail::Out out(base + ".node" + suffix);
    out << m.points.size() << " 3 0 0\n";
    for (size_t i = 0; i < m.points.size(); ++i) {
      const Vec3& p = m.points[i];
      out << i + 1 << ' ' << p.x << ' ' << p.y << ' ' << p.z << '\n';
    }
    out.finish();
  }
  if (!m.tets.empty()) {
    detail::Out out(base + ".ele" + suffix);
    const bool quad = !m.tet_mid.empty();
    out << m.tets.size() << (quad ? " 10 1\n" : " 4 1\n");
    for (size_t i = 0; i < m.tets.size(); ++i) {
      const Tetrahedron& t = m.tets[i];
      out << i + 1 << ' ' << t.v[0] + 1 << ' ' << t.v[1] + 1 << ' ' << t.v[2] + 1 << ' ' << t.v[3] + 1 << ' ';
      if (quad)
        for (int j : kTetgenMid) out << m.tet_mid[i][j] + 1 << ' ';
      out << t.region << '\n';
    }
    out.finish();
  }
  if (!m.triangles.empty()) {
    detail::Out out(base + ".face" + suffix);
    const bool quad = !m.triangle_mid.empty();
    out << m.triangles.size() << " 1\n";
    // Without an .ele file nothing says a triangle's sides.
    const bool without_sides = m.tets.empty();
    for (size_t i = 0; i < m.triangles.size(); ++i) {
      const Triangle& t = m.triangles[i];
      const std::array<int, 3> v = without_sides ? detail::corners_without_sides(t) : t.v;
      out << i + 1 << ' ' << v[0] + 1 << ' ' << v[1] + 1 << ' ' << v[2] + 1 << ' ';
      if (quad)
        for (int x : without_sides ? detail::mid_nodes_without_sides(t, m.triangle_mid[i]) : m.triangle_mid[i])
          out << x + 1 << ' ';
      out << t.face << '\n';
    }
    out.finish();
  }
  for (const std::string& other : tetgen_set_files(path))
    if (std::find(written.begin(), written.end(), other) == written.end()) std::remove(other.c_str());
}

}  // namespace

Format make_tetgen_format() {
  return {"tetgen", {".node", ".ele", ".face"}, true, read_tetgen, write_tetgen, tetgen_set_files};
}

}  // namespace vd::io
