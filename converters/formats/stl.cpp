// STL, ASCII and binary. Vertices are welded exactly on reading (STL repeats
// them per facet). Several ASCII solids become face ids, one per solid.
#include <cctype>
#include <cmath>

#include "formats.h"
#include "groups.h"
#include "io_util.h"

namespace vd::io {
namespace {

using detail::Cursor;

// Binary when the size matches the facet count at byte 80, which an ASCII
// file starting with "solid" practically never does; some binary files start
// with "solid" too, so the word alone decides nothing.
bool looks_binary(std::string_view data) {
  if (data.size() < 84) return false;
  uint32_t n;
  std::memcpy(&n, data.data() + 80, 4);
  const uint64_t expected = 84 + 50 * static_cast<uint64_t>(n);
  if (expected == data.size()) return true;
  size_t i = 0;
  while (i < data.size() && std::isspace(static_cast<unsigned char>(data[i]))) ++i;
  const bool solid_word = detail::starts_with_ci(data.substr(i), "solid");
  return !solid_word;  // an ASCII file starts with "solid"
}

Mesh read_binary(std::string_view data, const std::string& path) {
  Cursor in(data, path);
  in.skip_bytes(80, "the header");
  const uint32_t n = in.get<uint32_t>("the facet count");
  if (84 + 50 * static_cast<uint64_t>(n) > data.size())
    in.fail("the file is too short for its " + std::to_string(n) + " facets");
  Mesh m;
  m.points.reserve(3 * size_t{n});
  m.triangles.reserve(n);
  for (uint32_t f = 0; f < n; ++f) {
    float v[12];
    in.raw(v, sizeof v, "a facet");
    in.skip_bytes(2, "a facet attribute");
    Triangle t;
    for (int k = 0; k < 3; ++k) {
      const Vec3 p{v[3 + 3 * k], v[4 + 3 * k], v[5 + 3 * k]};
      if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
        in.fail("facet " + std::to_string(f) + " has a coordinate that is not a finite number");
      t.v[k] = static_cast<int>(m.points.size());
      m.points.push_back(p);
    }
    m.triangles.push_back(t);
  }
  return m;
}

void expect(Cursor& in, std::string_view word) {
  const std::string_view t = in.token(std::string(word).c_str());
  if (!detail::iequals(t, word))
    in.fail("expected '" + std::string(word) + "', found '" + std::string(t.substr(0, 40)) + "'");
}

Mesh read_ascii(std::string_view data, const std::string& path) {
  Cursor in(data, path);
  Mesh m;
  std::vector<std::string> names;
  std::vector<int> solid_of;  // per triangle
  std::vector<int> poly;
  while (!in.at_end()) {
    expect(in, "solid");
    std::string_view name = in.rest_of_line();
    while (!name.empty() && (name.front() == ' ' || name.front() == '\t')) name.remove_prefix(1);
    names.emplace_back(name);
    for (;;) {
      const std::string_view word = in.token("'facet' or 'endsolid'");
      if (detail::iequals(word, "endsolid")) {
        in.rest_of_line();
        break;
      }
      if (!detail::iequals(word, "facet"))
        in.fail("expected 'facet' or 'endsolid', found '" + std::string(word.substr(0, 40)) + "'");
      expect(in, "normal");
      for (int k = 0; k < 3; ++k) in.real("a normal component");
      expect(in, "outer");
      expect(in, "loop");
      poly.clear();
      for (;;) {
        const std::string_view w = in.token("'vertex' or 'endloop'");
        if (detail::iequals(w, "endloop")) break;
        if (!detail::iequals(w, "vertex"))
          in.fail("expected 'vertex' or 'endloop', found '" + std::string(w.substr(0, 40)) + "'");
        Vec3 p;
        p.x = in.real("a vertex x");
        p.y = in.real("a vertex y");
        p.z = in.real("a vertex z");
        poly.push_back(static_cast<int>(m.points.size()));
        m.points.push_back(p);
      }
      if (poly.size() < 3) in.fail("a facet has " + std::to_string(poly.size()) + " vertices");
      expect(in, "endfacet");
      for (size_t j = 1; j + 1 < poly.size(); ++j) {
        Triangle t;
        t.v = {poly[0], poly[j], poly[j + 1]};
        m.triangles.push_back(t);
        solid_of.push_back(static_cast<int>(names.size()) - 1);
      }
    }
  }
  if (names.empty()) in.fail("no solid in the file");
  // One unnamed solid carries no face information; several solids do.
  const bool tagged = names.size() > 1 || detail::id_from_name(names[0], "Face") >= 1;
  if (tagged) {
    const std::vector<int> ids = detail::face_ids_for_groups(names, m);
    for (size_t i = 0; i < m.triangles.size(); ++i) m.triangles[i].face = ids[static_cast<size_t>(solid_of[i])];
  }
  return m;
}

Mesh read_stl(const std::string& path) {
  const detail::FileBytes data(path);
  Mesh m = looks_binary(data) ? read_binary(data, path) : read_ascii(data, path);
  weld_coincident_points(m);
  drop_unused_points(m);
  return m;
}

Vec3 unit_normal(const Mesh& m, const std::array<int, 3>& v) {
  const Vec3 a = m.points[static_cast<size_t>(v[0])];
  return normalized(cross(m.points[static_cast<size_t>(v[1])] - a, m.points[static_cast<size_t>(v[2])] - a));
}

void write_ascii(const Mesh& m, const std::string& path) {
  detail::Out out(path);
  const bool tagged = m.has_face_tags();
  size_t i = 0;
  while (i < m.triangles.size() || i == 0) {
    // One solid per run of triangles with the same face id.
    const int face = i < m.triangles.size() ? m.triangles[i].face : kNoFace;
    const std::string name = tagged ? detail::face_name(m, face) : "vdmesh";
    out << "solid " << name << '\n';
    for (; i < m.triangles.size() && (!tagged || m.triangles[i].face == face); ++i) {
      const std::array<int, 3> corners = detail::corners_without_sides(m.triangles[i]);
      const Vec3 n = unit_normal(m, corners);
      out << "  facet normal " << n.x << ' ' << n.y << ' ' << n.z << "\n    outer loop\n";
      for (int v : corners) {
        const Vec3& p = m.points[static_cast<size_t>(v)];
        out << "      vertex " << p.x << ' ' << p.y << ' ' << p.z << '\n';
      }
      out << "    endloop\n  endfacet\n";
    }
    out << "endsolid " << name << '\n';
    if (m.triangles.empty()) break;
  }
  out.finish();
}

void write_binary(const Mesh& m, const std::string& path) {
  detail::Out out(path);
  std::string header = "binary STL written by vdmesh";
  header.resize(80, ' ');
  out << header;
  out.raw(static_cast<uint32_t>(m.triangles.size()));
  for (const Triangle& t : m.triangles) {
    const std::array<int, 3> corners = detail::corners_without_sides(t);
    const Vec3 n = unit_normal(m, corners);
    for (double c : {n.x, n.y, n.z}) out.raw(static_cast<float>(c));
    for (int v : corners) {
      const Vec3& p = m.points[static_cast<size_t>(v)];
      for (double c : {p.x, p.y, p.z}) out.raw(static_cast<float>(c));
    }
    out.raw(uint16_t{0});
  }
  out.finish();
}

void write_stl(const Mesh& m, const std::string& path, const WriteOptions& options) {
  if (options.binary)
    write_binary(m, path);
  else
    write_ascii(m, path);
}

}  // namespace

Format make_stl_format() { return {"stl", {".stl"}, false, read_stl, write_stl, {}}; }

}  // namespace vd::io
