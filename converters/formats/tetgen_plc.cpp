// TetGen piecewise linear complexes: .poly (facets of several polygons, with
// facet holes) and .smesh (one polygon per facet). Polygons are triangulated
// in their facet plane; the facet marker is the face id (else the facet's
// position, 1-based). The hole and region lists become region points.
// Writing gives one triangle per facet and the region points back.
#include <cmath>
#include <filesystem>
#include <map>

#include "geometry/triangle_index.h"
#include "mesh/disjoint_sets.h"

#include "surface/validate_surface.h"

#include "surface/orient_surface.h"
#include "formats.h"
#include "io_util.h"
#include "polygon_triangulation.h"
#include "tetgen_files.h"

namespace vd::io {
namespace {

using detail::Cursor;

Mesh read_plc(const std::string& path) {
  const bool poly = detail::extension_of(path) == ".poly";
  const detail::FileBytes data(path);
  Cursor in(data, path);
  in.set_comment('#');
  Mesh m;
  int first = 0;
  // Part 1: nodes, here or (count 0) in the .node file beside it.
  {
    if (in.at_end()) in.fail("empty file");
    const size_t mark = in.pos();  // after at_end(): seeking back crosses no line
    int64_t n;
    if (!Cursor::parse_int(in.token("the number of nodes"), n)) in.fail("expected the number of nodes");
    if (n == 0) {
      in.skip_line();
      const std::string node = detail::tetgen_base(path) + ".node";
      std::error_code ec;
      if (!std::filesystem::exists(node, ec)) in.fail("no nodes here and no " + node);
      const detail::FileBytes nodes(node);
      Cursor nin(nodes, node);
      nin.set_comment('#');
      first = detail::read_tetgen_nodes(nin, m);
    } else {
      in.seek(mark);
      first = detail::read_tetgen_nodes(in, m);
    }
  }
  // Part 2: facets.
  const uint64_t nf = in.count("the number of facets", data.size());
  const uint64_t markers = in.count("the boundary marker flag");
  in.skip_line();
  m.triangles.reserve(detail::capped(nf, data.size(), 8));
  std::vector<std::vector<int>> polygons;
  std::vector<Vec3> holes;
  for (uint64_t f = 0; f < nf; ++f) {
    polygons.clear();
    holes.clear();
    int face = static_cast<int>(std::min<uint64_t>(f + 1, INT32_MAX));
    if (poly) {
      const uint64_t np = in.count("the number of polygons", data.size());
      uint64_t nh = 0;
      if (in.line_has_more()) nh = in.count("the number of facet holes", data.size());
      if (in.line_has_more() && markers) face = in.int32("a facet marker");
      in.skip_line();
      for (uint64_t p = 0; p < np; ++p) {
        const uint64_t k = in.count("the number of polygon vertices", data.size());
        std::vector<int> loop;
        for (uint64_t j = 0; j < k; ++j) loop.push_back(detail::tetgen_vertex(in, m, first, "a polygon vertex"));
        polygons.push_back(std::move(loop));
        in.skip_line();
      }
      for (uint64_t h = 0; h < nh; ++h) {
        in.integer("a hole number");
        Vec3 p;
        p.x = in.real("a hole x");
        p.y = in.real("a hole y");
        p.z = in.real("a hole z");
        holes.push_back(p);
        in.skip_line();
      }
    } else {
      const uint64_t k = in.count("the number of facet vertices", data.size());
      std::vector<int> loop;
      for (uint64_t j = 0; j < k; ++j) loop.push_back(detail::tetgen_vertex(in, m, first, "a facet vertex"));
      if (in.line_has_more() && markers) face = in.int32("a facet marker");
      polygons.push_back(std::move(loop));
      in.skip_line();
    }
    for (const auto& t : detail::triangulate_facet(m.points, polygons, holes)) {
      Triangle tri;
      tri.v = t;
      tri.face = face < 0 ? kNoFace : face;
      m.triangles.push_back(tri);
    }
  }
  // Parts 3 and 4, optional: holes (made exterior) and region points (their
  // attribute is the region id). Read past until 2026-11-30, which meshed
  // tetgen_example.poly's two holes as regions and numbered its regions
  // 1 and 2 where TetGen's -A numbers them 10 and 20.
  auto point = [&in](const char* what) {
    in.integer(what);
    Vec3 p;
    for (int k = 0; k < 3; ++k) p[k] = in.real("a coordinate");
    return p;
  };
  if (!in.at_end()) {
    const uint64_t nh = in.count("the number of holes", data.size());
    in.skip_line();
    for (uint64_t h = 0; h < nh; ++h) {
      m.region_points.push_back({point("a hole number"), 0});
      in.skip_line();
    }
  }
  if (!in.at_end()) {
    const uint64_t nr = in.count("the number of regions", data.size());
    in.skip_line();
    for (uint64_t r = 0; r < nr; ++r) {
      const Vec3 p = point("a region number");
      const double attribute = in.real("a region attribute");
      // A whole number from 1 up is the region's id; TetGen takes any real
      // (0 is its "none"), which names no region here: the region keeps the
      // number vdmesh finds for it.
      if (attribute == std::floor(attribute) && attribute >= 1 && attribute <= kLargestRegionId)
        m.region_points.push_back({p, static_cast<int>(attribute)});
      in.skip_line();  // a volume bound may follow
    }
  }
  // TetGen's facets carry no orientation; vdmesh's facets do (normal into
  // `front`), so orient them as a solid's boundary.
  orient_consistently(m);
  return m;
}

// A point inside each region and in each cavity (region 0 enclosed by the
// surface) for a mesh that has no region points of its own: a PLC written
// from a volume mesh or a tagged surface had empty lists, and meshing it again
// (TetGen, or vdmesh) filled the holes (tetgen_example.poly: +5.2 % volume)
// and numbered the regions anew (a CAD ring's two solids came back swapped).
// A region's point is its largest tetrahedron's centroid. Without
// tetrahedra, and for cavities, it is a point just off the roundest facet
// on that side, at most a hundredth of its inradius off, and nearer that
// facet than to any other: a fixed offset put a thin slot's hole point
// inside the solid around it, and TetGen then carved the solid away.
std::vector<RegionPoint> points_naming_regions(const Mesh& m) {
  std::vector<RegionPoint> points;
  std::map<int, std::pair<double, Vec3>> inside;  // region -> (size, point)
  for (const Tetrahedron& t : m.tets) {
    if (t.region <= 0) continue;
    const double volume = std::abs(detail::tet_det(m, t.v));
    auto& best = inside[t.region];
    if (volume > best.first) {
      Vec3 c{};
      for (int v : t.v) c = c + 0.25 * m.points[static_cast<size_t>(v)];
      best = {volume, c};
    }
  }
  auto corners = [&m](const Triangle& t) {
    return std::array<Vec3, 3>{m.points[static_cast<size_t>(t.v[0])], m.points[static_cast<size_t>(t.v[1])],
                               m.points[static_cast<size_t>(t.v[2])]};
  };
  auto inradius = [](const std::array<Vec3, 3>& p) {
    const double perimeter = norm(p[1] - p[0]) + norm(p[2] - p[1]) + norm(p[0] - p[2]);
    return perimeter > 0 ? norm(cross(p[1] - p[0], p[2] - p[0])) / perimeter : 0.0;
  };
  // Shells of facets with the exterior on one side (the other a region, or
  // tetrahedra without one), joined across edges.
  std::vector<int> outer;
  for (size_t i = 0; i < m.triangles.size(); ++i) {
    const Triangle& t = m.triangles[i];
    if ((t.front == 0) != (t.back == 0)) outer.push_back(static_cast<int>(i));
  }
  DisjointSets shells(outer.size());
  std::map<std::pair<int, int>, int> edge_owner;
  for (size_t k = 0; k < outer.size(); ++k) {
    const Triangle& t = m.triangles[static_cast<size_t>(outer[k])];
    for (int e = 0; e < 3; ++e) {
      const int u = t.v[e], w = t.v[(e + 1) % 3];
      const auto [it, fresh] = edge_owner.emplace(std::minmax(u, w), static_cast<int>(k));
      if (!fresh) shells.join(it->second, static_cast<int>(k));
    }
  }
  // Per shell: its volume seen from the exterior (each facet turned to face
  // region 0: positive when the exterior is around it, negative for a cavity;
  // about a corner of the shell, for precision away from the origin) and its
  // roundest facet, with the side the exterior is on.
  struct Shell {
    double volume = 0;
    Vec3 origin{};
    bool have_origin = false;
    double inradius = 0;
    int facet = -1;
    bool front = false;
  };
  std::map<int, Shell> shell;
  for (size_t k = 0; k < outer.size(); ++k) {
    const Triangle& t = m.triangles[static_cast<size_t>(outer[k])];
    const bool exterior_in_front = t.front == 0;
    const std::array<Vec3, 3> p = corners(t);
    Shell& s = shell[shells.find(static_cast<int>(k))];
    if (!s.have_origin) s.origin = p[0], s.have_origin = true;
    s.volume += (exterior_in_front ? 1 : -1) * dot(p[0] - s.origin, cross(p[1] - s.origin, p[2] - s.origin)) / 6;
    const double r = inradius(p);
    if (r > s.inradius) s.inradius = r, s.facet = outer[k], s.front = exterior_in_front;
  }
  // Facets to place points off: a cavity's roundest, and without
  // tetrahedra each region's roundest.
  std::vector<std::pair<int, std::pair<int, bool>>> wanted;  // (region, (facet, front))
  for (const auto& [root, s] : shell)
    if (s.volume < 0 && s.facet >= 0) wanted.push_back({0, {s.facet, s.front}});
  if (m.tets.empty()) {
    std::map<int, std::pair<double, std::pair<int, bool>>> roundest;
    for (size_t i = 0; i < m.triangles.size(); ++i) {
      const Triangle& t = m.triangles[i];
      const double r = inradius(corners(t));
      for (const bool front : {true, false}) {
        const int region = front ? t.front : t.back;
        if (region <= 0 || t.front == t.back) continue;
        auto& best = roundest[region];
        if (r > best.first) best = {r, {static_cast<int>(i), front}};
      }
    }
    for (const auto& [region, best] : roundest)
      if (best.first > 0) wanted.push_back({region, best.second});
  }
  if (!wanted.empty()) {
    std::vector<std::array<Vec3, 3>> all;
    all.reserve(m.triangles.size());
    for (const Triangle& t : m.triangles) all.push_back(corners(t));
    const TriangleIndex index(all);
    for (const auto& [region, at] : wanted) {
      const auto [facet, front] = at;
      const std::array<Vec3, 3>& p = all[static_cast<size_t>(facet)];
      const Vec3 centroid = (1.0 / 3) * (p[0] + p[1] + p[2]);
      const Vec3 n = normalized(cross(p[1] - p[0], p[2] - p[0]));
      double offset = 0.01 * inradius(p);
      for (int tries = 0; tries < 60 && offset > 0; ++tries, offset *= 0.5) {
        const Vec3 q = centroid + (front ? offset : -offset) * n;
        if (index.distance(facet, q) <= index.closest(q).distance) {
          points.push_back({q, region});
          break;
        }
      }
    }
  }
  for (const auto& [region, best] : inside)
    if (best.first > 0) points.push_back({best.second, region});
  return points;
}

void write_plc(const Mesh& m, const std::string& path, const WriteOptions&) {
  const bool poly = detail::extension_of(path) == ".poly";
  detail::Out out(path);
  const detail::SurfacePoints used = detail::surface_points(m);
  out << "# written by vdmesh\n" << used.kept.size() << " 3 0 0\n";
  for (size_t i = 0; i < used.kept.size(); ++i) {
    const Vec3& p = m.points[used.kept[i]];
    out << i + 1 << ' ' << p.x << ' ' << p.y << ' ' << p.z << '\n';
  }
  out << m.triangles.size() << " 1\n";
  for (const Triangle& t : m.triangles) {
    if (poly) out << "1 0 " << t.face << "\n";
    const std::array<int, 3> v = detail::corners_without_sides(t);
    out << "3 " << used.number[v[0]] + 1 << ' ' << used.number[v[1]] + 1 << ' ' << used.number[v[2]] + 1;
    if (!poly) out << ' ' << t.face;
    out << '\n';
  }
  const std::vector<RegionPoint> derived = m.region_points.empty() ? points_naming_regions(m) : std::vector<RegionPoint>{};
  std::vector<const RegionPoint*> holes, regions;
  for (const RegionPoint& r : m.region_points.empty() ? derived : m.region_points)
    (r.region == 0 ? holes : regions).push_back(&r);
  for (const auto* list : {&holes, &regions}) {
    out << list->size() << '\n';
    for (size_t i = 0; i < list->size(); ++i) {
      const RegionPoint& r = *(*list)[i];
      out << i + 1 << ' ' << r.at.x << ' ' << r.at.y << ' ' << r.at.z;
      if (list == &regions) out << ' ' << r.region;
      out << '\n';
    }
  }
  out.finish();
}

}  // namespace

Format make_tetgen_plc_format() { return {"tetgen-plc", {".poly", ".smesh"}, false, read_plc, write_plc, {}}; }

}  // namespace vd::io
