// The exact Delaunay tetrahedralization of a growing vertex set (CGAL,
// exact predicates). It is the reference oracle of facet Delaunayhood, tells
// which facets a new vertex can affect, and gives the final tetrahedra.
// CGAL stays behind this header so that most of vdmesh compiles without it.
#pragma once

#include <array>
#include <atomic>
#include <cstdint>
#include <memory>
#include <vector>

#include "mesh/mesh.h"

namespace vd {

class DelaunayTetrahedralization {
 public:
  DelaunayTetrahedralization();
  ~DelaunayTetrahedralization();
  DelaunayTetrahedralization(const DelaunayTetrahedralization&) = delete;
  DelaunayTetrahedralization& operator=(const DelaunayTetrahedralization&) = delete;

  // Inserts points[first..] (spatially sorted). Vertex ids are the indices
  // into `points`. Pre: the points are pairwise distinct. Looks at `cancel`
  // every few thousand points (hundreds of thousands take seconds).
  void insert(const std::vector<Vec3>& points, int first = 0, const std::atomic<bool>* cancel = nullptr);
  // Inserts one point with id `id` (== number of vertices so far), near
  // vertex `hint` when >= 0. Returns the ids of its Delaunay neighbours: every
  // face that appeared or disappeared with it has all its vertices among them
  // and `id`.
  std::vector<int> insert_one(const Vec3& p, int id, int hint = -1);
  // The finite faces that inserting p would take away: those between two
  // tetrahedra whose circumspheres hold p (exact). Nothing is changed.
  // False, with `faces` empty, when p is a vertex or outside the convex hull.
  // `boundary`: the faces around them, which p's new tetrahedra stand on
  // (-1 for the infinite vertex).
  bool faces_taken_by(const Vec3& p, std::vector<std::array<int, 3>>& faces,
                      std::vector<std::array<int, 3>>* boundary = nullptr) const;

  int number_of_vertices() const;
  // 3 once four vertices are not in one plane; until then the
  // tetrahedralization has no tetrahedra (a triangulation of a plane, a
  // line, a point), and nothing that asks about tetrahedra may be called.
  int dimension() const;
  // Back to no vertices: a step that is undone has the tetrahedralization
  // of the vertices before it built again (one insert), instead of a copy
  // kept of it all along.
  void clear();
  // Vertex ids of the finite tetrahedron containing p (exact point location),
  // or {-1, -1, -1, -1} when p is outside the convex hull.
  std::array<int, 4> locate(const Vec3& p) const;
  // Is triangle (a, b, c) a face of the tetrahedralization?
  bool has_facet(int a, int b, int c) const;
  // has_facet for every triangle at once, by one sweep over the
  // tetrahedra: a search of each facet's star was a tenth of a surface-only
  // run at 89k facets.
  std::vector<char> has_facets(const std::vector<Triangle>& triangles) const;
  // The vertices opposite triangle (a, b, c) in the two tetrahedra beside it,
  // -1 for a side on the convex hull (the infinite vertex); {-2, -2} when the
  // triangle is not a face.
  std::array<int, 2> facet_apexes(int a, int b, int c) const;
  // facet_apexes for every triangle at once, in no particular order within
  // a pair: by one sweep over the tetrahedra unless they are far more than
  // the triangles (a facet's star search costs as much as 60 tetrahedra of
  // the sweep; it was half of the sliver pass's set-up on a sphere).
  std::vector<std::array<int, 2>> facet_apexes(const std::vector<Triangle>& triangles) const;
  bool has_edge(int a, int b) const;
  // Ids of the Delaunay neighbours of vertex `id`.
  std::vector<int> neighbours(int id) const;

  // The finite tetrahedra, numbered 0 .. n-1 by number_cells() (which
  // returns n; valid until the next insertion): cell(t) gives one's
  // vertices, positively oriented, and cell_across(t, i) the tetrahedron
  // across its face i (opposite vertex i), -1 on the convex hull. Read in
  // place: copies of both tables were a sixth of the peak memory.
  int number_cells() const;
  std::array<int, 4> cell(int t) const;
  int cell_across(int t, int i) const;
  // A scan of cell(t) in order of t asks for cell t + kCellsAhead here: the
  // vertex ids lie anywhere in memory, and fetched ahead they arrive while
  // the cells between are worked on (with the facet index's bit table, the
  // elephant's scans went 138 -> 90 ms).
  static constexpr int kCellsAhead = 8;
  void prefetch_cell(int t) const;
  // The faces on the convex hull as (tetrahedron, face index), numbered as
  // by the last number_cells().
  std::vector<std::array<int, 2>> hull_faces() const;
  // For every numbered tetrahedron, one of the tetrahedra it reaches across
  // faces not marked in `walls` (bit i of walls[t]: face i of t): two are
  // joined exactly when they get the same. Here rather than over
  // cell_across, because it is memory-bound (a tenth of a run once): one
  // pass in cell order, the neighbours fetched some cells ahead, joining
  // them in a union-find, instead of a walk that waited on each neighbour.
  std::vector<int> joined_cells(const std::vector<std::uint8_t>& walls) const;

  // Region labels kept in the tetrahedra themselves, so that point location
  // answers a region and the tetrahedra of a later insertion inherit one
  // without the regions being built again. label_cells gives numbered
  // tetrahedron t the label labels[t] (those beyond the hull 0) and ends the
  // numbering. Any insertion leaves the new tetrahedra unlabelled (-1)
  // until label_star labels those around the new vertex.
  void label_cells(const std::vector<int>& labels);
  // The label of the tetrahedron containing p (exact), 0 outside the hull.
  int label_at(const Vec3& p) const;
  void label_star(int vertex, int label);
  // Labels each unlabelled tetrahedron with the region of one of its vertices
  // from `first` on: vertex_region[id - first] (the interior vertices just
  // inserted, each strictly inside its region). Right only when no facet
  // stopped being a face meanwhile: then every new tetrahedron has such a
  // vertex and lies in its region. Throws std::logic_error for an unlabelled
  // tetrahedron with none.
  void label_new_cells(int first, const std::vector<int>& vertex_region);
  // Labels the tetrahedra a change of the surface left unlabelled (those
  // an insertion made) or touched (on either side of a facet in `changed`,
  // sorted vertex triples of the facets added or removed since the last
  // labelling, which still is a face): from a facet of `surface` they lie
  // on (its front or back region, by orientation), else from a labelled
  // neighbour across a face that is no facet. The others keep their label:
  // a tetrahedron no insertion removed and no changed facet bounds lies on
  // the side of the surface it lay on. False when some tetrahedron stays
  // unlabelled (the caller builds the regions in full).
  bool relabel_changed_cells(const Mesh& surface, const std::vector<std::array<int, 3>>& changed);
  // The finite tetrahedra with a label above 0, as tetrahedra of that region,
  // in the order number_cells() would give; *exterior, when given, counts
  // those labelled 0. Throws std::logic_error when a tetrahedron is
  // unlabelled.
  std::vector<Tetrahedron> labelled_cells(int* exterior = nullptr) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace vd
