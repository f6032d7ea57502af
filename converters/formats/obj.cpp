// Wavefront OBJ: vertices and polygons; `g`/`o` groups become face ids.
// Texture and normal indices are ignored, polygons are triangulated
// (triangulate_polygon).
#include <algorithm>
#include <map>

#include "formats.h"
#include "groups.h"
#include "io_util.h"
#include "polygon_triangulation.h"

namespace vd::io {
namespace {

using detail::Cursor;

// The vertex part of "v", "v/vt", "v//vn", "v/vt/vn".
std::string_view vertex_part(std::string_view t) { return t.substr(0, t.find('/')); }

Mesh read_obj(const std::string& path) {
  const detail::FileBytes data(path);
  Cursor in(data, path);
  in.set_comment('#');
  Mesh m;
  std::vector<std::string> names;
  std::map<std::string, int, std::less<>> group_of_name;
  int group = -1;                // current group, -1 before any
  std::vector<int> group_of;     // per triangle
  std::vector<int> poly;
  int64_t max_index = 0;
  size_t max_index_line = 0;
  while (!in.at_end()) {
    const std::string_view key = in.token_in_line();
    if (key == "v") {
      Vec3 p;
      p.x = in.real_in_line("a vertex x");
      p.y = in.real_in_line("a vertex y");
      p.z = in.real_in_line("a vertex z");
      m.points.push_back(p);
      in.skip_line();  // w or colours
    } else if (key == "f") {
      poly.clear();
      const size_t line = in.line();
      for (std::string_view t = in.token_in_line();; t = in.token_in_line()) {
        // A line ending in '\' goes on on the next (refused as a bad face
        // vertex until 2026-11-30).
        if (t == "\\" && !in.line_has_more()) {
          in.skip_line();
          continue;
        }
        if (t.empty()) break;
        int64_t i;
        if (!Cursor::parse_int(vertex_part(t), i) || i == 0)
          in.fail("bad face vertex '" + std::string(t.substr(0, 40)) + "'");
        // Negative indices count back from the last vertex read so far.
        if (i < 0) i += static_cast<int64_t>(m.points.size()) + 1;
        if (i < 1) in.fail("face vertex '" + std::string(t.substr(0, 40)) + "' does not exist");
        if (i > INT32_MAX) in.fail("face vertex index too large");
        if (i > max_index) {
          max_index = i;
          max_index_line = line;
        }
        poly.push_back(static_cast<int>(i - 1));
      }
      if (poly.size() < 3) in.fail("a face has " + std::to_string(poly.size()) + " vertices");
      // A polygon naming vertices still to come (the format allows it)
      // is taken convex.
      const bool known = *std::max_element(poly.begin(), poly.end()) < static_cast<int>(m.points.size());
      for (const auto& corners : known ? detail::triangulate_polygon(m.points, poly) : detail::fan(poly)) {
        Triangle t;
        t.v = corners;
        m.triangles.push_back(t);
        group_of.push_back(group);
      }
      in.skip_line();
    } else if (key == "g" || key == "o") {
      std::string_view name = in.rest_of_line();
      while (!name.empty() && (name.front() == ' ' || name.front() == '\t')) name.remove_prefix(1);
      if (name.empty()) name = "default";
      auto it = group_of_name.find(name);
      if (it == group_of_name.end()) {
        it = group_of_name.emplace(std::string(name), static_cast<int>(names.size())).first;
        names.emplace_back(name);
      }
      group = it->second;
    } else {
      in.skip_line();  // vt, vn, s, usemtl, mtllib, l, p, ...
    }
  }
  if (static_cast<uint64_t>(max_index) > m.points.size())
    throw InputError(path + ":" + std::to_string(max_index_line) + ": face vertex " + std::to_string(max_index) +
                     " does not exist (" + std::to_string(m.points.size()) + " vertices)");
  if (!names.empty()) {
    // Faces before the first group form a group of their own.
    bool ungrouped = false;
    for (int g : group_of) ungrouped |= g < 0;
    if (ungrouped) names.push_back("default");
    const std::vector<int> ids = detail::face_ids_for_groups(names, m);
    for (size_t i = 0; i < m.triangles.size(); ++i)
      m.triangles[i].face = ids[group_of[i] < 0 ? names.size() - 1 : static_cast<size_t>(group_of[i])];
  }
  return m;
}

void write_obj(const Mesh& m, const std::string& path, const WriteOptions&) {
  detail::Out out(path);
  out << "# written by vdmesh\n";
  const detail::SurfacePoints used = detail::surface_points(m);
  for (const int i : used.kept) out << "v " << m.points[i].x << ' ' << m.points[i].y << ' ' << m.points[i].z << '\n';
  const bool tagged = m.has_face_tags();
  int current = kNoFace - 1;
  for (const Triangle& t : m.triangles) {
    if (tagged && t.face != current) {
      current = t.face;
      out << "g " << detail::face_name(m, t.face) << '\n';
    }
    const std::array<int, 3> v = detail::corners_without_sides(t);
    out << "f " << used.number[v[0]] + 1 << ' ' << used.number[v[1]] + 1 << ' ' << used.number[v[2]] + 1 << '\n';
  }
  out.finish();
}

}  // namespace

Format make_obj_format() { return {"obj", {".obj"}, false, read_obj, write_obj, {}}; }

}  // namespace vd::io
