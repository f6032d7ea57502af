// Geomview OFF: a surface of polygons, no tags. Polygons are triangulated
// (triangulate_polygon).
#include "formats.h"
#include "io_util.h"
#include "polygon_triangulation.h"

namespace vd::io {
namespace {

using detail::Cursor;

Mesh read_off(const std::string& path) {
  const detail::FileBytes data(path);
  Cursor in(data, path);
  in.set_comment('#');
  const std::string_view header = in.token("the OFF header");
  // Prefixes ST, C, N (texture, colour, normal) only add per-vertex columns.
  std::string_view kind = header;
  while (!kind.empty() && (kind[0] == 'S' || kind[0] == 'T' || kind[0] == 'C' || kind[0] == 'N'))
    kind.remove_prefix(1);
  if (kind != "OFF") in.fail("not an OFF file (header '" + std::string(header.substr(0, 20)) + "')");
  if (in.line_has_more()) {
    const std::string_view t = in.token_in_line();
    int64_t dummy;
    if (!Cursor::parse_int(t, dummy)) in.fail("binary or non-3D OFF is not supported");
    in.seek(in.pos() - t.size());
  }
  const uint64_t nv = in.count("the vertex count");
  const uint64_t nf = in.count("the face count");
  in.count("the edge count");
  Mesh m;
  m.points.reserve(detail::capped(nv, data.size(), 6));
  for (uint64_t i = 0; i < nv; ++i) {
    Vec3 p;
    p.x = in.real("a vertex x");
    p.y = in.real("a vertex y");
    p.z = in.real("a vertex z");
    m.points.push_back(p);
    in.skip_line();  // colours, normals
  }
  m.triangles.reserve(detail::capped(nf, data.size(), 8));
  std::vector<int> poly;
  for (uint64_t f = 0; f < nf; ++f) {
    const uint64_t k = in.count("the vertex count of a face", data.size());
    if (k < 3) in.fail("face " + std::to_string(f) + " has " + std::to_string(k) + " vertices");
    poly.clear();
    for (uint64_t j = 0; j < k; ++j) {
      const int64_t v = in.integer("a face vertex index");
      if (v < 0 || static_cast<uint64_t>(v) >= nv)
        in.fail("face vertex " + std::to_string(v) + " does not exist (" + std::to_string(nv) + " vertices)");
      poly.push_back(static_cast<int>(v));
    }
    in.skip_line();  // face colour
    for (const auto& corners : detail::triangulate_polygon(m.points, poly)) {
      Triangle t;
      t.v = corners;
      m.triangles.push_back(t);
    }
  }
  return m;
}

void write_off(const Mesh& m, const std::string& path, const WriteOptions&) {
  detail::Out out(path);
  const detail::SurfacePoints used = detail::surface_points(m);
  out << "OFF\n" << used.kept.size() << ' ' << m.triangles.size() << " 0\n";
  for (const int i : used.kept) out << m.points[i].x << ' ' << m.points[i].y << ' ' << m.points[i].z << '\n';
  for (const Triangle& t : m.triangles) {
    const std::array<int, 3> v = detail::corners_without_sides(t);
    out << "3 " << used.number[v[0]] << ' ' << used.number[v[1]] << ' ' << used.number[v[2]] << '\n';
  }
  out.finish();
}

}  // namespace

Format make_off_format() { return {"off", {".off"}, false, read_off, write_off, {}}; }

}  // namespace vd::io
