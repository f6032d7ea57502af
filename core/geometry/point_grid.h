// A dynamic spatial index of the growing vertex set: points are appended over
// time and sometimes moved, and the oracles ask for the ids inside a box or a
// ball. A uniform grid: the cell size follows the average spacing
// (bounding-box volume / number of points), and the grid rebuilds itself when
// the set has doubled or spread well beyond the box it was sized for, so a
// query stays proportional to the points it returns.
//
// The cells are one dense array over the box (about one cell per point),
// each the head and tail of a list threaded through the points: a hashed
// grid's look-ups and per-cell vectors were a tenth of the 6.6M-tetrahedron
// box's run, in the interior vertices' spacing test. A point beyond the
// box sits in the border cell nearest to it until such points are many.
// A cell that comes to hold many points (a model crowded into a corner of a
// far-field box) lists them in sub-cells of its own.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "mesh/mesh.h"

namespace vd {

class PointGrid {
 public:
  // Indexes points[0..n) from scratch (ids are the indices).
  void build(const std::vector<Vec3>& points);
  // Point `id` was appended (id == size()) or moved to p.
  void update(int id, const Vec3& p);

  int size() const { return static_cast<int>(position_.size()); }
  // Indexes the points appended to `points` since the grid last saw them
  // (the oracles answer about the whole set even when a caller appended
  // points without telling them).
  void catch_up(const std::vector<Vec3>& points) {
    for (int id = size(); id < static_cast<int>(points.size()); ++id) update(id, points[static_cast<size_t>(id)]);
  }
  // Three distinct indexed points.
  bool has_triangle(int a, int b, int c) const {
    const int n = size();
    return a >= 0 && b >= 0 && c >= 0 && a < n && b < n && c < n && a != b && b != c && a != c;
  }
  const Vec3& position(int id) const { return position_[static_cast<size_t>(id)]; }
  // A box containing every indexed point (after moves it may be larger than
  // the tight one).
  const Vec3& lower() const { return lower_; }
  const Vec3& upper() const { return upper_; }

  // Ids of the points in the closed box [lo, hi], replacing `out`.
  void in_box(const Vec3& lo, const Vec3& hi, std::vector<int>& out) const;
  // Ids of the points in the closed ball, replacing `out`.
  void in_ball(const Vec3& centre, double radius, std::vector<int>& out) const;
  // Is any point in the closed ball? The same answer as in_ball's list being
  // non-empty, found at the first point: the interior candidates' spacing
  // test rejects most candidates (240k of 287k on gmsh_simple_plane.brep),
  // each on the first vertex it finds.
  bool any_in_ball(const Vec3& centre, double radius) const;

 private:
  using CellKey = std::array<std::int64_t, 3>;

  // The cell of p (clamped into the grid) and its index in the arrays.
  CellKey cell_of(const Vec3& p) const;
  size_t index_of(const CellKey& k) const {
    return (static_cast<size_t>(k[0]) * static_cast<size_t>(dims_[1]) + static_cast<size_t>(k[1])) *
               static_cast<size_t>(dims_[2]) + static_cast<size_t>(k[2]);
  }
  void insert_into_cell(int id);
  void remove_from_cell(int id);
  // Calls stop(id) on each point in the closed box [lo, hi], in the order
  // in_box lists them, until it returns true; true when one did.
  template <class Stop>
  bool find_in_box(const Vec3& lo, const Vec3& hi, Stop&& stop) const;
  void grow_bounds(const Vec3& p);
  bool needs_rebuild() const;
  void rebuild();

  // A cell that comes to hold more than kCrowdedCell points lists them in
  // kFine^3 sub-cells instead (FineCells). Points clustered in a small part
  // of the box (a model in a far-field box: gmsh_simple_plane.brep's
  // aircraft, 79k surface vertices where the average spacing over the box is
  // 0.06 and its chords 1e-5) crowded 1,800 into a point's cell on average,
  // and every query near them scanned those: the interior vertices' spacing
  // test was 17 of that run's 54 s (31 s now). Evenly spread points never
  // fill a cell so: they keep their cells and the order queries list them in.
  // Halving the cells at the rebuild while they were crowded, within 64
  // cells per point, saved 0.2 s more there, for a pass over the points at
  // every rebuild on every input: dropped.
  static constexpr int kCrowdedCell = 64;
  static constexpr int kFine = 16;
  struct FineCells {
    std::vector<int> head, tail;
  };
  // The sub-cell of p in cell `key`, clamped into it.
  size_t fine_index(const CellKey& key, const Vec3& p) const;
  std::array<std::int64_t, 3> fine_key(const CellKey& key, const Vec3& p) const;
  void list(std::vector<int>& head, std::vector<int>& tail, size_t at, int id);
  void unlist(std::vector<int>& head, std::vector<int>& tail, size_t at, int id);
  // Moves the points listed in `cell` into sub-cells.
  void split_cell(const CellKey& key, size_t cell);

  std::vector<Vec3> position_;
  std::vector<int> count_;        // per cell: its points
  std::vector<int> fine_of_;      // per cell: its sub-cells in fine_, or -1
  std::vector<FineCells> fine_;
  std::vector<int> head_, tail_;  // per cell: first and last point, -1 when empty
  std::vector<int> next_;         // per point: the next one in its cell, -1 at the end
  std::array<std::int64_t, 3> dims_{1, 1, 1};
  long occupied_ = 0;  // cells with a point
  long outside_ = 0;   // points placed beyond the grid since it was built
  double cell_size_ = 1;
  Vec3 origin_;  // corner of cell (0, 0, 0); fixed between rebuilds
  Vec3 lower_, upper_;
  bool has_bounds_ = false;
  // What the current cell size was chosen for.
  int built_for_count_ = 0;
  double built_for_extent_ = 0;
};

// Exact emptiness of the spheres the oracles test, with the convention of
// predicates.h: a vertex on the sphere occupies it. Only the defining
// vertices themselves are ignored (by id).

// Ids (other than a, b, c) inside or on the equatorial sphere of (a, b, c),
// replacing `out`; empty when the sphere is empty. A collinear triangle has no
// sphere: returns false then (and leaves `out` empty).
bool equatorial_sphere_occupants(const PointGrid& grid, int a, int b, int c, std::vector<int>& out);
// Is the circumsphere of tetrahedron (a, b, c, d) free of all other vertices?
// A flat tetrahedron answers false.
bool circumsphere_is_empty(const PointGrid& grid, int a, int b, int c, int d);

}  // namespace vd
