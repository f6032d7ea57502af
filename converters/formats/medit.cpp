// Medit / INRIA .mesh (ASCII): Vertices with a reference, Triangles with
// ref = face id, Tetrahedra with ref = region. Other sections are skipped.
// Second order as Gmsh writes it (`gmsh -order 2 -o X.mesh`): TrianglesP2
// and TetrahedraP2, corners then mid-edge nodes on the edges in VTK's and
// vdmesh's order (01, 12, 20, 03, 13, 23), not Gmsh's own MSH order.
#include <algorithm>
#include <map>

#include "formats.h"
#include "io_util.h"
#include "mesh/error.h"

namespace vd::io {
namespace {

using detail::Cursor;

// Numbers per entry of the sections we skip.
int skipped_section_width(const std::string& key) {
  static const std::map<std::string, int> widths = {
      {"edges", 3},          {"corners", 1},          {"ridges", 1},
      {"requiredvertices", 1}, {"requirededges", 1},    {"requiredtriangles", 1},
      {"quadrilaterals", 5},   {"hexahedra", 9},        {"prisms", 7},
      {"pyramids", 6},         {"normals", 3},          {"tangents", 3},
      {"normalatvertices", 2}, {"tangentatedges", 3},   {"normalattrianglevertices", 3},
      {"requiredquadrilaterals", 1}, {"requiredtetrahedra", 1}, {"requiredhexahedra", 1},
      {"tangentatvertices", 2}, {"normalatquadrilateralvertices", 3}};
  auto it = widths.find(key);
  return it == widths.end() ? -1 : it->second;
}

Mesh read_medit(const std::string& path) {
  const detail::FileBytes data(path);
  Cursor in(data, path);
  in.set_comment('#');
  Mesh m;
  uint64_t nv = 0;
  auto vertex = [&](const char* what) {
    const int64_t v = in.integer(what);
    if (v < 1 || static_cast<uint64_t>(v) > nv)
      in.fail(std::string(what) + " " + std::to_string(v) + " does not exist (" + std::to_string(nv) + " vertices)");
    return static_cast<int>(v - 1);
  };
  bool have_vertices = false;
  while (!in.at_end()) {
    const std::string key = detail::to_lower(in.token("a keyword"));
    if (key == "meshversionformatted") {
      const int64_t v = in.integer("the mesh version");
      if (v < 1 || v > 4) in.fail("unsupported mesh version " + std::to_string(v));
    } else if (key == "dimension") {
      const int64_t d = in.integer("the dimension");
      if (d != 3) in.fail("only 3D meshes are supported (Dimension " + std::to_string(d) + ")");
    } else if (key == "vertices") {
      if (have_vertices) in.fail("a second Vertices section");
      have_vertices = true;
      nv = in.count("the number of vertices", INT32_MAX);
      m.points.reserve(detail::capped(nv, data.size(), 8));
      for (uint64_t i = 0; i < nv; ++i) {
        Vec3 p;
        p.x = in.real("a vertex x");
        p.y = in.real("a vertex y");
        p.z = in.real("a vertex z");
        in.integer("a vertex reference");
        m.points.push_back(p);
      }
    } else if (key == "triangles" || key == "trianglesp2") {
      const bool p2 = key == "trianglesp2";
      if (!m.triangles.empty()) in.fail("a second section of triangles");
      const uint64_t n = in.count("the number of triangles", data.size());
      m.triangles.reserve(detail::capped(n, data.size(), 8));
      for (uint64_t i = 0; i < n; ++i) {
        Triangle t;
        for (int& v : t.v) v = vertex("a triangle vertex");
        if (p2) {
          TriMidNodes mid;
          for (int& v : mid) v = vertex("a triangle mid-edge node");
          m.triangle_mid.push_back(mid);
        }
        t.face = in.int32("a triangle reference");
        m.triangles.push_back(t);
      }
    } else if (key == "tetrahedra" || key == "tetrahedrap2") {
      const bool p2 = key == "tetrahedrap2";
      if (!m.tets.empty()) in.fail("a second section of tetrahedra");
      const uint64_t n = in.count("the number of tetrahedra", data.size());
      m.tets.reserve(detail::capped(n, data.size(), 10));
      for (uint64_t i = 0; i < n; ++i) {
        Tetrahedron t;
        for (int& v : t.v) v = vertex("a tetrahedron vertex");
        if (p2) {
          TetMidNodes mid;
          for (int& v : mid) v = vertex("a tetrahedron mid-edge node");
          m.tet_mid.push_back(mid);
        }
        // Reference 0 is "none" (TetGen's -g and meshio write it for
        // untagged meshes), not region 0, the exterior: read as that, a
        // TetGen mesh was "region 0: volume 2" until 2026-11-30.
        t.region = in.int32("a tetrahedron reference");
        if (t.region == 0) t.region = kUnknownRegion;
        m.tets.push_back(t);
      }
    } else if (key == "end") {
      break;
    } else {
      const int width = skipped_section_width(key);
      if (width < 0) {
        // A number where a keyword belongs: the section before has more
        // numbers per entry than its keyword says (Gmsh heads 10-node
        // tetrahedra "Tetrahedra" when second order is asked after meshing).
        int64_t number = 0;
        if (Cursor::parse_int(key, number))
          in.fail("expected a section keyword, found the number " + key.substr(0, 40) +
                  ": the section before has more numbers per entry than its keyword says (second-order elements "
                  "under a first-order keyword?)");
        in.fail("unknown section '" + key.substr(0, 40) + "'");
      }
      const uint64_t n = in.count("a section size", data.size());
      // Elements vdmesh has no place for were skipped without a word.
      if (n > 0 && (key == "quadrilaterals" || key == "hexahedra" || key == "prisms" || key == "pyramids"))
        in.fail(std::to_string(n) + " " + key + ": vdmesh reads triangles and tetrahedra only, and would lose them");
      for (uint64_t i = 0; i < n * static_cast<uint64_t>(width); ++i) in.token("a section value");
    }
  }
  detail::require_valid(m, path);
  detail::sides_from_tets(m);
  return m;
}

void write_medit(const Mesh& m, const std::string& path, const WriteOptions&) {
  // Until 2026-11-29 the mid-edge nodes went out as loose vertices beside
  // first-order elements, with no word; then second order was refused.
  const bool tri_p2 = !m.triangle_mid.empty(), tet_p2 = !m.tet_mid.empty();
  detail::Out out(path);
  out << "MeshVersionFormatted 2\nDimension 3\n\nVertices\n" << m.points.size() << '\n';
  for (const Vec3& p : m.points) out << p.x << ' ' << p.y << ' ' << p.z << " 0\n";
  if (!m.triangles.empty()) {
    out << (tri_p2 ? "\nTrianglesP2\n" : "\nTriangles\n") << m.triangles.size() << '\n';
    // Without tetrahedra nothing says a triangle's sides (the reader takes
    // them from the tetrahedra).
    for (size_t i = 0; i < m.triangles.size(); ++i) {
      const Triangle& t = m.triangles[i];
      const std::array<int, 3> v = m.tets.empty() ? detail::corners_without_sides(t) : t.v;
      out << v[0] + 1 << ' ' << v[1] + 1 << ' ' << v[2] + 1;
      if (tri_p2) {
        const TriMidNodes x = m.tets.empty() ? detail::mid_nodes_without_sides(t, m.triangle_mid[i]) : m.triangle_mid[i];
        for (int v : x) out << ' ' << v + 1;
      }
      out << ' ' << std::max(t.face, 0) << '\n';
    }
  }
  if (!m.tets.empty()) {
    out << (tet_p2 ? "\nTetrahedraP2\n" : "\nTetrahedra\n") << m.tets.size() << '\n';
    for (size_t i = 0; i < m.tets.size(); ++i) {
      const Tetrahedron& t = m.tets[i];
      out << t.v[0] + 1 << ' ' << t.v[1] + 1 << ' ' << t.v[2] + 1 << ' ' << t.v[3] + 1;
      if (tet_p2) {
        for (int v : m.tet_mid[i]) out << ' ' << v + 1;
      }
      // Reference 0 is no region (and no face id) to the readers.
      out << ' ' << std::max(t.region, 0) << '\n';
    }
  }
  out << "\nEnd\n";
  out.finish();
}

}  // namespace

Format make_medit_format() { return {"medit", {".mesh"}, true, read_medit, write_medit, {}}; }

}  // namespace vd::io
