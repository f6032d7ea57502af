#include "vtk_common.h"

#include "io_util.h"

namespace vd::io::detail {

namespace {

const std::vector<double>* array(const VtkCells& c, std::initializer_list<const char*> names) {
  for (const char* n : names) {
    auto it = c.data.find(n);
    if (it != c.data.end() && it->second.size() + 1 == c.offsets.size()) return &it->second;
  }
  return nullptr;
}

int as_int(double v) {
  return v >= -2147483648.0 && v <= 2147483647.0 ? static_cast<int>(v) : kUnknownRegion;
}

}  // namespace

Mesh mesh_from_vtk(std::vector<Vec3> points, const VtkCells& c, const std::string& where) {
  Mesh m;
  m.points = std::move(points);
  const size_t ncells = c.types.size();
  if (c.offsets.size() != ncells + 1) throw InputError(where + ": the cell offsets do not match the cell types");
  const auto* tags = array(c, {"gmsh:physical", "CellEntityIds", "medit:ref", "cell_tags"});
  const auto* region = array(c, {"region"});
  const auto* face = array(c, {"face"});
  const auto* front = array(c, {"front"});
  const auto* back = array(c, {"back"});
  if (!region) region = tags;
  if (!face) face = tags;
  const int64_t np = static_cast<int64_t>(m.points.size());
  for (size_t i = 0; i < ncells; ++i) {
    const int64_t b = c.offsets[i], e = c.offsets[i + 1];
    if (b < 0 || e < b || e > static_cast<int64_t>(c.conn.size()))
      throw InputError(where + ": cell " + std::to_string(i) + " has bad offsets");
    const int type = c.types[i];
    int k = 0;
    if (type == kVtkTet) k = 4;
    else if (type == kVtkQuadraticTet) k = 10;
    else if (type == kVtkTriangle) k = 3;
    else if (type == kVtkQuadraticTriangle) k = 6;
    else continue;  // vertices, lines, quads, hexahedra...
    if (e - b != k)
      throw InputError(where + ": cell " + std::to_string(i) + " of type " + std::to_string(type) + " has " +
                       std::to_string(e - b) + " nodes, not " + std::to_string(k));
    int v[10];
    for (int j = 0; j < k; ++j) {
      const int64_t n = c.conn[static_cast<size_t>(b + j)];
      if (n < 0 || n >= np)
        throw InputError(where + ": cell " + std::to_string(i) + " refers to point " + std::to_string(n) +
                         ", which does not exist (" + std::to_string(np) + " points)");
      v[j] = static_cast<int>(n);
    }
    if (k >= 4 && k != 6) {
      Tetrahedron t;
      t.v = {v[0], v[1], v[2], v[3]};
      t.region = region ? as_int((*region)[i]) : kUnknownRegion;
      m.tets.push_back(t);
      if (k == 10) m.tet_mid.push_back({v[4], v[5], v[6], v[7], v[8], v[9]});
    } else {
      Triangle t;
      t.v = {v[0], v[1], v[2]};
      t.face = face ? as_int((*face)[i]) : kNoFace;
      if (t.face < 0) t.face = kNoFace;
      t.front = front ? as_int((*front)[i]) : kUnknownRegion;
      t.back = back ? as_int((*back)[i]) : kUnknownRegion;
      m.triangles.push_back(t);
      if (k == 6) m.triangle_mid.push_back({v[3], v[4], v[5]});
    }
  }
  require_valid(m, where);
  sides_from_tets(m);
  return m;
}

}  // namespace vd::io::detail
