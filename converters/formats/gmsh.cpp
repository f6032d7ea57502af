// Writes Gmsh MSH 2.2 and 4.1, ASCII and binary. Regions become physical
// volumes, face ids physical surfaces; in 4.1 one volume entity per region
// and one surface entity per face id, each volume listing its bounding
// surfaces (+s when the surface's normal points out of it). A face on
// several faces' groups (Mesh::face_groups) is in each physical surface:
// its entity lists them all (4.1), its elements are written once per group
// (2.2, as Gmsh does). Element tags follow the elements' positions, so the
// reader restores the order.
#include <algorithm>
#include <cstdlib>
#include <map>
#include <set>

#include "formats.h"
#include "gmsh.h"
#include "io_util.h"

namespace vd::io {
namespace {

using detail::Out;

// Gmsh needs positive tags: regions and faces <= 0 (unknown, exterior) go to
// a spare tag without a physical group.
struct Tags {
  std::vector<int> tet_tag, tri_tag;
  std::set<int> regions, faces;  // physical groups
  int spare_region = 0, spare_face = 0;
};

Tags make_tags(const Mesh& m) {
  Tags t;
  int max_r = 0, max_f = 0;
  for (const Tetrahedron& e : m.tets) max_r = std::max(max_r, e.region);
  for (const Triangle& e : m.triangles) {
    max_f = std::max(max_f, e.face);
    max_r = std::max({max_r, e.front, e.back});
  }
  t.spare_region = max_r + 1;
  t.spare_face = max_f + 1;
  for (const Tetrahedron& e : m.tets) {
    t.tet_tag.push_back(e.region > 0 ? e.region : t.spare_region);
    if (e.region > 0) t.regions.insert(e.region);
  }
  for (const Triangle& e : m.triangles) {
    t.tri_tag.push_back(e.face > 0 ? e.face : t.spare_face);
    if (e.face > 0)
      for (const int g : face_groups_of(m, e.face)) t.faces.insert(g);
    // Regions seen only beside triangles (a surface mesh) still get volumes.
    if (e.front > 0) t.regions.insert(e.front);
    if (e.back > 0) t.regions.insert(e.back);
  }
  return t;
}

void write_physical_names(Out& out, const Mesh& m, const Tags& t) {
  out << "$PhysicalNames\n" << t.regions.size() + t.faces.size() << '\n';
  for (int f : t.faces) out << "2 " << f << " \"" << detail::face_name(m, f) << "\"\n";
  for (int r : t.regions) out << "3 " << r << " \"" << detail::region_name(m, r) << "\"\n";
  out << "$EndPhysicalNames\n";
}

void write_format(Out& out, const char* version, bool binary) {
  out << "$MeshFormat\n" << version << (binary ? " 1 8\n" : " 0 8\n");
  if (binary) {
    out.raw(int32_t{1});
    out << '\n';
  }
  out << "$EndMeshFormat\n";
}

int tri_type(const Mesh& m) { return m.triangle_mid.empty() ? detail::kMshTriangle : detail::kMshTriangle6; }
int tet_type(const Mesh& m) { return m.tet_mid.empty() ? detail::kMshTet : detail::kMshTet10; }

// Node indices (0-based) of triangle / tetrahedron i in Gmsh order.
// `without_sides`: the file cannot say the triangle's sides (MSH 2.2 without
// tetrahedra), and it is turned out of its solid (corners_without_sides).
int tri_nodes_written(const Mesh& m, size_t i, int* n, bool without_sides) {
  const Triangle& t = m.triangles[i];
  const std::array<int, 3> v = without_sides ? detail::corners_without_sides(t) : t.v;
  n[0] = v[0], n[1] = v[1], n[2] = v[2];
  if (m.triangle_mid.empty()) return 3;
  const TriMidNodes mid =
      without_sides ? detail::mid_nodes_without_sides(t, m.triangle_mid[i]) : m.triangle_mid[i];
  for (int k = 0; k < 3; ++k) n[3 + k] = mid[k];
  return 6;
}
int tri_nodes(const Mesh& m, size_t i, int* n) { return tri_nodes_written(m, i, n, false); }

int tet_nodes(const Mesh& m, size_t i, int* n) {
  const Tetrahedron& t = m.tets[i];
  for (int k = 0; k < 4; ++k) n[k] = t.v[k];
  if (m.tet_mid.empty()) return 4;
  TetMidNodes mid = m.tet_mid[i];
  detail::swap_tet10_gmsh(mid);
  for (int k = 0; k < 6; ++k) n[4 + k] = mid[k];
  return 10;
}

void write22(const Mesh& m, Out& out, bool binary) {
  const Tags t = make_tags(m);
  write_format(out, "2.2", binary);
  write_physical_names(out, m, t);
  out << "$Nodes\n" << m.points.size() << '\n';
  for (size_t i = 0; i < m.points.size(); ++i) {
    const Vec3& p = m.points[i];
    if (binary) {
      out.raw(static_cast<int32_t>(i + 1));
      const double xyz[3] = {p.x, p.y, p.z};
      out.raw_n(xyz, 3);
    } else {
      out << i + 1 << ' ' << p.x << ' ' << p.y << ' ' << p.z << '\n';
    }
  }
  out << (binary ? "\n$EndNodes\n" : "$EndNodes\n");
  // The physical surfaces of each face id (none for the spare).
  std::map<int, std::vector<int>> physicals;
  size_t written_triangles = 0;
  for (size_t i = 0; i < m.triangles.size(); ++i) {
    auto it = physicals.find(t.tri_tag[i]);
    if (it == physicals.end())
      it = physicals.emplace(t.tri_tag[i], t.tri_tag[i] == t.spare_face ? std::vector<int>{0}
                                                                          : face_groups_of(m, t.tri_tag[i])).first;
    written_triangles += it->second.size();
  }
  out << "$Elements\n" << written_triangles + m.tets.size() << '\n';
  int n[10];
  size_t tag = 0;
  auto element = [&](int type, int physical, int entity, int k) {
    ++tag;
    if (binary) {
      int32_t v[13] = {static_cast<int32_t>(tag), physical, entity};
      for (int j = 0; j < k; ++j) v[3 + j] = n[j] + 1;
      out.raw_n(v, static_cast<size_t>(3 + k));
    } else {
      out << tag << ' ' << type << " 2 " << physical << ' ' << entity;
      for (int j = 0; j < k; ++j) out << ' ' << n[j] + 1;
      out << '\n';
    }
  };
  auto block_header = [&](int type, size_t count) {
    if (!binary || count == 0) return;
    out.raw(static_cast<int32_t>(type)), out.raw(static_cast<int32_t>(count)), out.raw(int32_t{2});
  };
  block_header(tri_type(m), written_triangles);
  for (size_t i = 0; i < m.triangles.size(); ++i) {
    const int k = tri_nodes_written(m, i, n, m.tets.empty());
    const int entity = t.tri_tag[i];
    for (const int physical : physicals.at(entity)) element(tri_type(m), physical, entity, k);
  }
  block_header(tet_type(m), m.tets.size());
  for (size_t i = 0; i < m.tets.size(); ++i) {
    const int k = tet_nodes(m, i, n);
    const int entity = t.tet_tag[i];
    element(tet_type(m), t.regions.count(entity) ? entity : 0, entity, k);
  }
  out << (binary ? "\n$EndElements\n" : "$EndElements\n");
}

struct Box {
  Vec3 lo{1e300, 1e300, 1e300}, hi{-1e300, -1e300, -1e300};
  void add(const Vec3& p) {
    for (int k = 0; k < 3; ++k) lo[k] = std::min(lo[k], p[k]), hi[k] = std::max(hi[k], p[k]);
  }
  bool empty() const { return lo.x > hi.x; }
};

// Writers of 4.1 values: size_t and int in binary, text otherwise.
struct Writer41 {
  Out& out;
  bool binary;
  void size(uint64_t v, char sep = ' ') {
    if (binary) out.raw(v);
    else out << static_cast<long long>(v) << sep;
  }
  void integer(int v, char sep = ' ') {
    if (binary) out.raw(static_cast<int32_t>(v));
    else out << v << sep;
  }
  void real(double v, char sep = ' ') {
    if (binary) out.raw(v);
    else out << v << sep;
  }
  void end_line() {
    if (!binary) out.replace_last('\n');
  }
};

void write41(const Mesh& m, Out& out, bool binary) {
  const Tags t = make_tags(m);
  Writer41 w{out, binary};
  write_format(out, "4.1", binary);
  write_physical_names(out, m, t);

  // Entities and their elements, in tag order.
  std::map<int, std::vector<int>> surf_elems, vol_elems;  // element indices, 4 bytes each
  for (size_t i = 0; i < m.triangles.size(); ++i) surf_elems[t.tri_tag[i]].push_back(static_cast<int>(i));
  for (size_t i = 0; i < m.tets.size(); ++i) vol_elems[t.tet_tag[i]].push_back(static_cast<int>(i));
  for (int r : t.regions) vol_elems[r];  // regions beside triangles only
  std::map<int, Box> surf_box, vol_box;
  std::map<int, std::set<int>> bounding;  // volume -> signed surface tags
  for (size_t i = 0; i < m.triangles.size(); ++i) {
    const Triangle& e = m.triangles[i];
    const int s = t.tri_tag[i];
    for (int v : e.v) surf_box[s].add(m.points[static_cast<size_t>(v)]);
    if (e.back > 0) bounding[e.back].insert(s);
    if (e.front > 0 && e.front != e.back) bounding[e.front].insert(-s);
  }
  for (size_t i = 0; i < m.tets.size(); ++i)
    for (int v : m.tets[i].v) vol_box[t.tet_tag[i]].add(m.points[static_cast<size_t>(v)]);
  for (const auto& [r, faces] : bounding)
    for (int s : faces) {
      // A volume without tetrahedra gets the box of its surfaces.
      Box& b = vol_box[r];
      const Box& sb = surf_box[std::abs(s)];
      if (!sb.empty()) b.add(sb.lo), b.add(sb.hi);
    }
  if (surf_elems.empty() && vol_elems.empty()) vol_elems[1];  // nodes need an entity

  out << "$Entities\n";
  if (binary) out.raw(uint64_t{0}), out.raw(uint64_t{0});
  else out << "0 0 ";
  w.size(surf_elems.size());
  w.size(vol_elems.size());
  w.end_line();
  auto entity = [&](int tag, const Box& b, const std::vector<int>& physicals) {
    const Box box = b.empty() ? Box{{0, 0, 0}, {0, 0, 0}} : b;
    w.integer(tag);
    for (int k = 0; k < 3; ++k) w.real(box.lo[k]);
    for (int k = 0; k < 3; ++k) w.real(box.hi[k]);
    w.size(physicals.size());
    for (const int p : physicals) w.integer(p);
  };
  for (const auto& [s, elems] : surf_elems) {
    entity(s, surf_box[s], s == t.spare_face ? std::vector<int>{} : face_groups_of(m, s));
    w.size(0);
    w.end_line();
  }
  for (const auto& [r, elems] : vol_elems) {
    entity(r, vol_box[r], t.regions.count(r) ? std::vector<int>{r} : std::vector<int>{});
    const std::set<int>& b = bounding[r];
    w.size(b.size());
    for (int s : b) w.integer(s);
    w.end_line();
  }
  out << (binary ? "\n$EndEntities\n" : "$EndEntities\n");

  // All nodes in one block on the first volume (or surface) entity.
  const size_t np = m.points.size();
  out << "$Nodes\n";
  w.size(np ? 1 : 0), w.size(np), w.size(np ? 1 : 0), w.size(np);
  w.end_line();
  if (np) {
    const bool on_volume = !vol_elems.empty();
    w.integer(on_volume ? 3 : 2);
    w.integer(on_volume ? vol_elems.begin()->first : surf_elems.begin()->first);
    w.integer(0);
    w.size(np);
    w.end_line();
    if (binary) {
      for (size_t i = 0; i < np; ++i) out.raw(static_cast<uint64_t>(i + 1));
      static_assert(sizeof(Vec3) == 3 * sizeof(double), "points are written as they lie");
      out.raw_n(m.points.data(), np);
    } else {
      for (size_t i = 0; i < np; ++i) out << i + 1 << '\n';
      for (const Vec3& p : m.points) out << p.x << ' ' << p.y << ' ' << p.z << '\n';
    }
  }
  out << (binary ? "\n$EndNodes\n" : "$EndNodes\n");

  const size_t ne = m.triangles.size() + m.tets.size();
  size_t blocks = 0;
  for (const auto& [s, e] : surf_elems) blocks += !e.empty();
  for (const auto& [r, e] : vol_elems) blocks += !e.empty();
  out << "$Elements\n";
  w.size(blocks), w.size(ne), w.size(ne ? 1 : 0), w.size(ne);
  w.end_line();
  int n[10];
  auto block = [&](int dim, int tag, int type, const std::vector<int>& elems, size_t tag_offset,
                   int (*nodes)(const Mesh&, size_t, int*)) {
    if (elems.empty()) return;
    w.integer(dim), w.integer(tag), w.integer(type), w.size(elems.size());
    w.end_line();
    for (size_t i : elems) {
      const int k = nodes(m, i, n);
      if (binary) {
        uint64_t v[11] = {static_cast<uint64_t>(i + tag_offset + 1)};
        for (int j = 0; j < k; ++j) v[1 + j] = static_cast<uint64_t>(n[j] + 1);
        out.raw_n(v, static_cast<size_t>(1 + k));
      } else {
        out << i + tag_offset + 1;
        for (int j = 0; j < k; ++j) out << ' ' << n[j] + 1;
        out << '\n';
      }
    }
  };
  for (const auto& [s, elems] : surf_elems) block(2, s, tri_type(m), elems, 0, tri_nodes);
  for (const auto& [r, elems] : vol_elems) block(3, r, tet_type(m), elems, m.triangles.size(), tet_nodes);
  out << (binary ? "\n$EndElements\n" : "$EndElements\n");
}

void write_gmsh(const Mesh& m, const std::string& path, const WriteOptions& options) {
  Out out(path);
  if (options.msh_version == 22)
    write22(m, out, options.binary);
  else
    write41(m, out, options.binary);
  out.finish();
}

}  // namespace

Format make_gmsh_format() { return {"gmsh", {".msh"}, true, detail::read_gmsh, write_gmsh, {}}; }

}  // namespace vd::io
