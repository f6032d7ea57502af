// What the legacy .vtk and XML .vtu formats share: cell types, the cell data
// arrays vdmesh writes (region, face, front, back) and those of other
// programs it reads.
#pragma once

#include <cstddef>
#include <cstdint>
#include <map>
#include <string>
#include <string_view>
#include <vector>

#include "io_util.h"
#include "mesh/mesh.h"

namespace vd::io::detail {

constexpr int kVtkTriangle = 5, kVtkTet = 10, kVtkQuadraticTriangle = 22, kVtkQuadraticTet = 24;

// A stored number's type; the two formats name them their own way.
enum class ValueType { Int8, UInt8, Int16, UInt16, Int32, UInt32, Int64, UInt64, Float32, Float64, Unknown };

// Bytes per value; 0 for Unknown.
inline size_t value_size(ValueType t) {
  switch (t) {
    case ValueType::Int8: case ValueType::UInt8: return 1;
    case ValueType::Int16: case ValueType::UInt16: return 2;
    case ValueType::Int32: case ValueType::UInt32: case ValueType::Float32: return 4;
    case ValueType::Unknown: return 0;
    default: return 8;
  }
}

// Nodes of the cell types vdmesh keeps (tetrahedra and triangles, first and
// second order); 0 for every other type.
inline int vtk_element_nodes(int type) {
  return type == kVtkTet ? 4 : type == kVtkQuadraticTet ? 10 : type == kVtkTriangle ? 3 : type == kVtkQuadraticTriangle ? 6 : 0;
}

inline bool vtk_is_tet(int type) { return type == kVtkTet || type == kVtkQuadraticTet; }
inline bool vtk_is_triangle(int type) { return type == kVtkTriangle || type == kVtkQuadraticTriangle; }

// Cells skipped without loss: empty cells, vertices and lines (VTK_EMPTY_CELL,
// VERTEX, POLY_VERTEX, LINE, POLY_LINE, QUADRATIC_EDGE, CUBIC_LINE,
// LAGRANGE_CURVE, BEZIER_CURVE). Other cells that are no triangle or
// tetrahedron vdmesh has no place for: a mesh of tetrahedra and wedges was
// read as its tetrahedra, a hexahedron as nothing, exit 0, until 2026-11-30.
inline bool vtk_is_point_or_line(int type) {
  return type <= 4 || type == 21 || type == 35 || type == 68 || type == 75;
}

// The tetrahedra and triangles among cell types, first and second order.
struct VtkElementCounts {
  size_t tets = 0, tets10 = 0, tris = 0, tris6 = 0;
  long first_lost = -1;  // the first cell vdmesh would lose, -1 when none
  explicit VtkElementCounts(const std::vector<uint8_t>& types) {
    for (size_t i = 0; i < types.size(); ++i) {
      const uint8_t t = types[i];
      tets += vtk_is_tet(t);
      tets10 += t == kVtkQuadraticTet;
      tris += vtk_is_triangle(t);
      tris6 += t == kVtkQuadraticTriangle;
      if (first_lost < 0 && !vtk_is_tet(t) && !vtk_is_triangle(t) && !vtk_is_point_or_line(t))
        first_lost = static_cast<long>(i);
    }
  }
  // "cell 7 has VTK type 13 (a wedge): ..." for the first lost cell.
  std::string lost_text(const std::vector<uint8_t>& types) const {
    const int t = types[static_cast<size_t>(first_lost)];
    const char* name = t == 9 || t == 23 || t == 28 ? "a quadrilateral"
                       : t == 12 || t == 25 || t == 29 ? "a hexahedron"
                       : t == 13 || t == 26 ? "a wedge"
                       : t == 14 || t == 27 ? "a pyramid"
                       : t == 7 ? "a polygon"
                       : t == 42 ? "a polyhedron"
                                  : "neither a triangle nor a tetrahedron of order 1 or 2";
    return "cell " + std::to_string(first_lost) + " has VTK type " + std::to_string(t) + " (" + name +
           "): vdmesh reads triangles and tetrahedra of order 1 or 2 only, and would lose it";
  }
  // First- and second-order cells of one kind cannot share the mesh's arrays.
  bool mixed_order() const { return (tets10 && tets10 != tets) || (tris6 && tris6 != tris); }
};

// Cell data arrays other programs write their tags in, in order of
// preference; "region" and "face" win over them.
constexpr const char* kVtkTagArrays[] = {"gmsh:physical", "CellEntityIds", "medit:ref", "cell_tags"};

// What one cell data array sets: a tetrahedron's region, a triangle's face,
// front or back.
struct VtkCellRoles {
  bool region = false, face = false, front = false, back = false;
  bool any() const { return region || face || front || back; }
};

// Takes one cell data array's values in cell order and puts each into the
// tetrahedron or triangle that cell became (other cells are skipped).
class VtkCellDataSink {
 public:
  VtkCellDataSink(Mesh& m, VtkCellRoles roles) : m_(m), r_(roles) {}
  void put(int type, double value) {
    const int v = value >= -2147483648.0 && value <= 2147483647.0 ? static_cast<int>(value) : kUnknownRegion;
    if (vtk_is_tet(type)) {
      if (r_.region) m_.tets[tet_].region = v;
      ++tet_;
    } else if (vtk_is_triangle(type)) {
      Triangle& t = m_.triangles[tri_++];
      if (r_.face) t.face = v < 0 ? kNoFace : v;
      if (r_.front) t.front = v;
      if (r_.back) t.back = v;
    }
  }

 private:
  Mesh& m_;
  VtkCellRoles r_;
  size_t tet_ = 0, tri_ = 0;
};

// The cells of `m` as the writers emit them, tetrahedra then triangles, read
// straight from the mesh: building the arrays first tripled a writer's peak
// memory on a 1M-tetrahedron mesh.
class VtkCellView {
 public:
  // Cell data arrays, in the order written. A triangle's region is the one
  // behind it; a tetrahedron has no face, front or back (-1).
  static constexpr const char* kDataNames[4] = {"region", "face", "front", "back"};

  explicit VtkCellView(const Mesh& m)
      : m_(m),
        tets_(m.tets.size()),
        tet_nodes_(m.tet_mid.empty() ? 4 : 10),
        tri_nodes_(m.triangle_mid.empty() ? 3 : 6) {}
  size_t size() const { return tets_ + m_.triangles.size(); }
  size_t connectivity_size() const { return tets_ * tet_nodes_ + m_.triangles.size() * tri_nodes_; }
  int nodes(size_t cell) const { return cell < tets_ ? tet_nodes_ : tri_nodes_; }
  // Where cell's nodes end in the connectivity (VTU's offsets).
  int64_t end(size_t cell) const {
    return cell < tets_ ? int64_t(cell + 1) * tet_nodes_
                        : int64_t(tets_) * tet_nodes_ + int64_t(cell - tets_ + 1) * tri_nodes_;
  }
  int node(size_t cell, int j) const {
    if (cell < tets_) return j < 4 ? m_.tets[cell].v[j] : m_.tet_mid[cell][j - 4];
    const size_t t = cell - tets_;
    return j < 3 ? m_.triangles[t].v[j] : m_.triangle_mid[t][j - 3];
  }
  // Node k of the connectivity (all cells' nodes in a row). Divided by
  // constants, which the compiler turns into multiplications: a division by
  // a run-time count per node was a 64-bit divide each.
  int flat_node(size_t k) const {
    const size_t in_tets = tets_ * static_cast<size_t>(tet_nodes_);
    if (k < in_tets) return tet_nodes_ == 4 ? node(k / 4, static_cast<int>(k % 4)) : node(k / 10, static_cast<int>(k % 10));
    k -= in_tets;
    return tri_nodes_ == 3 ? node(tets_ + k / 3, static_cast<int>(k % 3)) : node(tets_ + k / 6, static_cast<int>(k % 6));
  }
  int type(size_t cell) const {
    if (cell < tets_) return tet_nodes_ == 4 ? kVtkTet : kVtkQuadraticTet;
    return tri_nodes_ == 3 ? kVtkTriangle : kVtkQuadraticTriangle;
  }
  int data(int array, size_t cell) const {
    if (cell < tets_) return array == 0 ? m_.tets[cell].region : -1;
    const Triangle& t = m_.triangles[cell - tets_];
    return array == 0 ? t.back : array == 1 ? t.face : array == 2 ? t.front : t.back;
  }

 private:
  const Mesh& m_;
  size_t tets_;
  int tet_nodes_, tri_nodes_;
};

// Region and face names (Solid1, Face3), which VTK has no place for: the
// bytes of "region <id> <name>" and "face <id> <name>" lines in an unsigned
// char array of the data set's field data, which VTK and ParaView read as
// numbers (meshio too in .vtu; it drops it from .vtk) and vdmesh reads back
// (both formats: a .vtu or .vtk gave Region1 for Solid1, and a deck's
// *SOLID SECTION, ELSET=Solid1 named nothing).
inline constexpr const char* kVtkNamesArray = "vdmesh_names";

// One line per name (a name with a line break in it is left out).
inline std::string vtk_names_text(const Mesh& m) {
  std::string text;
  for (const auto& [kind, names] : {std::pair{"region", &m.region_names}, std::pair{"face", &m.face_names}})
    for (const auto& [id, name] : *names)
      if (!name.empty() && name.find_first_of("\r\n") == std::string::npos)
        text += std::string(kind) + " " + std::to_string(id) + " " + name + "\n";
  return text;
}

// Reads vtk_names_text's lines back; other lines are skipped.
inline void read_vtk_names_text(std::string_view text, Mesh& m) {
  while (!text.empty()) {
    const size_t end = std::min(text.find('\n'), text.size());
    const std::string_view line = text.substr(0, end);
    text.remove_prefix(std::min(end + 1, text.size()));
    const size_t a = line.find(' ');
    if (a == std::string_view::npos) continue;
    const size_t b = line.find(' ', a + 1);
    if (b == std::string_view::npos || b + 1 >= line.size()) continue;
    int64_t id = 0;
    if (!Cursor::parse_int(line.substr(a + 1, b - a - 1), id) || id < INT32_MIN || id > INT32_MAX) continue;
    const std::string_view kind = line.substr(0, a);
    auto& names = kind == "region" ? m.region_names : m.face_names;
    if (kind == "region" || kind == "face") names[static_cast<int>(id)] = std::string(line.substr(b + 1));
  }
}

}  // namespace vd::io::detail
