// The independent checks `vdmesh compare` applies, the same way, to the mesh
// of each mesher: they look only at the input surface and at the tetrahedra,
// points and tagged triangles read back from the mesher's output files, never
// at what a mesher says about its own result.
//
//  - validity: no inverted tetrahedron (det(v1-v0, v2-v0, v3-v0) <= 0), no
//    face shared by more than two tetrahedra;
//  - boundary conformity: the boundary of the tetrahedra (faces with one
//    tetrahedron, faces between two regions, and faces of the mesh's own
//    triangle list inside a region: internal sheets) lies on the input
//    surface, and every input facet is covered by it, both within
//    kConformityTolerance of the local edge length;
//  - tag survival: each boundary face carries the face id of the input facet
//    it lies on; the regions on both sides of each input facet are the ones
//    its tags name (when the input has region tags);
//  - volumes: each region's tetrahedra fill the volume the input facets
//    enclose for it (from the input tags, or, without tags, from the sides
//    on which the mesh put each region);
//  - counts and quality: vertices, tetrahedra, boundary vertices added,
//    dihedral angles, radius ratio, slivers.
#pragma once

#include <array>
#include <memory>
#include <string>
#include <vector>

#include "mesh/mesh.h"
#include "quality/tet_quality.h"

namespace vd {
class TriangleIndex;
}  // namespace vd

namespace vd::compare {

// Distances are compared with this fraction of the longest edge of the
// facet concerned. vdmesh moves surface vertices by 1e-4 of the local size in
// their tangent plane (README, random shift); flips within a face change the
// surface by the ridge angle they allow, which the checks report.
constexpr double kConformityTolerance = 1e-3;

// The input surface, indexed once for the checks of every result.
class InputSurface {
 public:
  explicit InputSurface(const Mesh& input);
  ~InputSurface();
  InputSurface(const InputSurface&) = delete;
  InputSurface& operator=(const InputSurface&) = delete;

  const Mesh& mesh() const { return mesh_; }
  const TriangleIndex& index() const { return *index_; }
  double diagonal() const { return diagonal_; }    // of the bounding box
  const Vec3& centre() const { return centre_; }   // of the bounding box
  Vec3 normal(int f) const { return normals_[static_cast<size_t>(f)]; }
  double longest_edge(int f) const { return longest_edge_[static_cast<size_t>(f)]; }
  bool degenerate(int f) const { return longest_edge_[static_cast<size_t>(f)] == 0 || norm(normals_[static_cast<size_t>(f)]) == 0; }
  long surface_vertices() const { return surface_vertices_; }
  bool region_tags() const { return region_tags_; }

 private:
  Mesh mesh_;
  std::unique_ptr<TriangleIndex> index_;
  std::vector<Vec3> normals_;
  std::vector<double> longest_edge_;
  double diagonal_ = 0;
  Vec3 centre_;
  long surface_vertices_ = 0;
  bool region_tags_ = false;
};

struct RegionVolume {
  int region = 0;
  long tets = 0;
  double volume = 0;     // sum of the tetrahedra
  double reference = 0;  // enclosed by the input facets
  double relative_error = 0;
};

struct MeshChecks {
  // Counts.
  long vertices = 0;                  // used by tetrahedra
  long tets = 0;
  long boundary_faces = 0;
  long boundary_vertices = 0;
  long boundary_vertices_added = 0;   // boundary vertices minus the input's surface vertices
  // Validity.
  long inverted = 0;
  long non_manifold_faces = 0;
  // Conformity with the input surface.
  long boundary_faces_off_input = 0;  // a vertex or the centroid farther than the tolerance from the input
  long input_facets_uncovered = 0;    // a vertex or the centroid farther than the tolerance from the boundary
  long degenerate_input_facets = 0;   // skipped by the two tests above
  double max_distance_to_input = 0;   // output boundary -> input surface, / bounding-box diagonal
  double max_distance_to_output = 0;  // input surface -> output boundary, / bounding-box diagonal
  // Tags.
  long boundary_faces_untagged = 0;   // in no triangle of the output: no face id
  long face_ids_wrong = 0;            // another face id than the input facet under it
  bool region_tags_checked = false;   // the input has region tags
  long facet_sides_wrong = 0;         // input facets with other regions on their sides than tagged
  long facet_sides_ambiguous = 0;     // input facets with two regions on one side
  // Volumes.
  std::string volume_reference;       // where the reference volumes come from
  std::vector<RegionVolume> regions;  // regions > 0 of the mesh or of the reference
  double max_relative_volume_error = 0;
  // Quality.
  QualitySummary quality;
  std::array<long, 90> dihedral_histogram_2deg{};  // all six angles of every tetrahedron

  bool valid() const { return tets > 0 && inverted == 0 && non_manifold_faces == 0; }
  bool conforming() const { return boundary_faces_off_input == 0 && input_facets_uncovered == 0; }
  bool tags_ok() const {
    return boundary_faces_untagged == 0 && face_ids_wrong == 0 && facet_sides_wrong == 0 && facet_sides_ambiguous == 0;
  }
  bool volumes_ok(double tolerance) const { return !regions.empty() && max_relative_volume_error <= tolerance; }
  // Every failed check in words; empty when all pass (volume tolerance given).
  std::vector<std::string> problems(double volume_tolerance) const;
};

// `result`: points, tetrahedra with regions > 0, and the triangles of the
// mesher's output with their face ids.
MeshChecks check_mesh(const InputSurface& input, const Mesh& result);

// Points strictly inside each region of a region-tagged input surface, one
// per region id > 0 (for TetGen's region list): a point a little behind a
// large facet of the region, kept only if no other facet is nearer to it.
// Regions for which no such point is found are left out.
std::vector<RegionPoint> region_points(const InputSurface& input);

}  // namespace vd::compare
