// The one mesh type of vdmesh: a surface (triangles with face ids and the
// regions on both sides) and optionally a volume (tetrahedra with a region).
// Readers produce it, the mesher consumes and produces it, writers write it.
//
// Conventions (README, "Conventions"):
//  - Region 0 is the exterior, regions are 1..N; kUnknownRegion when the input
//    carries no region information (the mesher then finds the regions).
//  - A triangle's normal (right-hand rule over v[0], v[1], v[2]) points into its
//    `front` region; `back` is the other side.
//  - A tetrahedron (v0, v1, v2, v3) is positive: det(v1-v0, v2-v0, v3-v0) > 0,
//    the orientation Gmsh, VTK, Abaqus and TetGen share.
//  - Indices are 0-based here; writers convert to each format's own base.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <map>
#include <string>
#include <vector>

namespace vd {

struct Vec3 {
  double x = 0, y = 0, z = 0;
  double& operator[](int i) { return i == 0 ? x : (i == 1 ? y : z); }
  double operator[](int i) const { return i == 0 ? x : (i == 1 ? y : z); }
};

inline Vec3 operator+(Vec3 a, Vec3 b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
inline Vec3 operator-(Vec3 a, Vec3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
inline Vec3 operator*(double s, Vec3 a) { return {s * a.x, s * a.y, s * a.z}; }
inline double dot(Vec3 a, Vec3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
inline Vec3 cross(Vec3 a, Vec3 b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
// Inline: the sliver pass's compass searches call it millions of times.
inline double norm(Vec3 a) { return std::sqrt(dot(a, a)); }
inline Vec3 normalized(Vec3 a) {
  const double n = norm(a);
  return n > 0 ? (1.0 / n) * a : a;
}
// The distance between the lines through p, q and through r, s (0 when they
// are parallel): how far a flip that swaps diagonal pq for rs moves the
// surface (Delaunayzation's flips, sliver case A).
inline double line_distance(Vec3 p, Vec3 q, Vec3 r, Vec3 s) {
  const Vec3 n = cross(q - p, s - r);
  const double len = norm(n);
  return len > 0 ? std::abs(dot(r - p, n)) / len : 0.0;
}

// The smallest axis-aligned box holding every point (both corners at the
// origin when there is none).
struct Box {
  Vec3 lo, hi;
};
inline Box bounding_box(const std::vector<Vec3>& points) {
  Box b;
  if (points.empty()) return b;
  b.lo = b.hi = points.front();
  for (const Vec3& p : points)
    for (int i = 0; i < 3; ++i) b.lo[i] = std::min(b.lo[i], p[i]), b.hi[i] = std::max(b.hi[i], p[i]);
  return b;
}

constexpr int kUnknownRegion = -1;
constexpr int kNoFace = -1;

// by_face[face] where it is set (> 0), else `otherwise`: a bound per CAD face
// (its chord height) beside one for the whole surface.
inline double face_value_or(const std::vector<double>& by_face, int face, double otherwise) {
  if (face >= 0 && static_cast<size_t>(face) < by_face.size() && by_face[static_cast<size_t>(face)] > 0)
    return by_face[static_cast<size_t>(face)];
  return otherwise;
}

struct Triangle {
  std::array<int, 3> v{};
  int face = kNoFace;           // topological face id (CAD face, input group)
  int front = kUnknownRegion;   // region the normal points into
  int back = kUnknownRegion;    // region on the other side
};

struct Tetrahedron {
  std::array<int, 4> v{};
  int region = kUnknownRegion;
};

// Second-order nodes, in the edge order of VTK and Abaqus: tetrahedron
// (01, 12, 20, 03, 13, 23), triangle (01, 12, 20). Gmsh swaps the last two
// tetrahedron edges (..., 03, 23, 13); its reader and writer convert.
using TetMidNodes = std::array<int, 6>;
using TriMidNodes = std::array<int, 3>;

// A point that names the region around it (TetGen's region list), or with
// region 0 makes it exterior (TetGen's hole list). Where the regions are
// found from the surface, the region holding the point takes its id.
struct RegionPoint {
  Vec3 at;
  int region = 0;
};

struct Mesh {
  std::vector<Vec3> points;
  std::vector<double> point_size;  // mesh size per point; empty when not given
  std::vector<Triangle> triangles;
  std::vector<Tetrahedron> tets;
  // Filled only for second order meshes (same length as triangles / tets).
  std::vector<TriMidNodes> triangle_mid;
  std::vector<TetMidNodes> tet_mid;
  // Optional names, e.g. from Gmsh physical groups or CAD ("Solid1", "Face3").
  std::map<int, std::string> region_names;
  std::map<int, std::string> face_names;
  // Faces whose facets belong to more than their own face's group: where
  // touching CAD solids are fused, one face of the result lies on two input
  // faces (caxif's Face67 on its Face82), and its facets carry one id.
  // Maps such an id to every face (group) its facets are part of, itself
  // among them only when it is an input face. Writers of named groups
  // (Abaqus surfaces and node sets, Gmsh physical groups) put the facets
  // into each; other formats keep the id (face_groups_of).
  std::map<int, std::vector<int>> face_groups;
  // Holes win over region points in the same region, as TetGen carves
  // holes before it labels regions.
  std::vector<RegionPoint> region_points;

  bool second_order() const { return !tet_mid.empty() || !triangle_mid.empty(); }
  bool has_region_tags() const;
  bool has_face_tags() const;
};

// The groups the facets of face `face` belong to: face_groups' entry, else
// the face alone.
std::vector<int> face_groups_of(const Mesh& m, int face);

// Face ids for pieces that may lie on several faces: piece i has id ids[i]
// (its first face) and lies on the faces groups[i] (empty or one: its own
// only). A piece on several faces keeps its id when every piece of that id
// lies on the same faces, else it gets an id of its own past `last_id`
// (one per list of faces). Returns Mesh::face_groups for the ids given.
std::map<int, std::vector<int>> number_shared_pieces(std::vector<int>& ids, const std::vector<std::vector<int>>& groups,
                                                     int last_id);

// Removes the points no triangle or tetrahedron uses and renumbers the rest
// in order. Returns the old -> new id map (-1: removed); empty when nothing
// was removed. A surface vertex that no facet uses would still be a vertex of
// the Delaunay tetrahedralization, and one a hair off the surface keeps the
// facets beside it from ever becoming Delaunay.
std::vector<int> drop_unused_points(Mesh& m);

// Points at the very same coordinates made one: every element's reference to
// a repeat goes to the first of them, and the repeats are left unused (for
// drop_unused_points). OFF and OBJ files may give a point once per part (two
// cubes touching at an edge: "coincident vertices", exit 3, until
// 2026-11-29); two coincident points cannot both be vertices of a Delaunay
// tetrahedralization. Returns how many points were repeats.
int weld_coincident_points(Mesh& m);

// 1 for each of the first `points` ids that is a vertex of a triangle, else 0.
std::vector<char> surface_vertex_flags(size_t points, const std::vector<Triangle>& triangles);

}  // namespace vd
