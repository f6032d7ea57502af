#include "delaunay/delaunay_tetrahedralization.h"

#include <CGAL/Delaunay_triangulation_3.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Triangulation_cell_base_with_info_3.h>
#include <CGAL/Triangulation_vertex_base_with_info_3.h>
#include <CGAL/spatial_sort.h>

#include <algorithm>
#include <functional>
#include <numeric>
#include <stdexcept>

#include "geometry/predicates.h"
#include "mesh/cancel.h"
#include "mesh/disjoint_sets.h"
#include "mesh/parallel.h"
#include "mesh/progress.h"
#include "mesh/tet_faces.h"

namespace vd {
namespace {
using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using Vb = CGAL::Triangulation_vertex_base_with_info_3<int, K>;
// Cells carry an int so that number_cells() numbers them without a hash map
// of handles (that map was a tenth of a run at 865k tetrahedra), or a region
// label (label_cells). New cells start at -1: a plain int would start
// indeterminate, and labelled_cells() must tell a cell no one labelled.
struct CellTag {
  int value = -1;
};
using Cb = CGAL::Triangulation_cell_base_with_info_3<CellTag, K>;
using Tds = CGAL::Triangulation_data_structure_3<Vb, Cb>;
using DT = CGAL::Delaunay_triangulation_3<K, Tds>;
using CGALPoint = K::Point_3;

CGALPoint to_cgal(const Vec3& p) { return {p.x, p.y, p.z}; }

// Spatial sort traits over vertex ids (CGAL reads the typedefs; at namespace
// scope, so the compiler does not take them for unused local ones).
struct SortByIndex {
  const std::vector<Vec3>* pts;
  using Point_3 = int;
  struct Less {
    const std::vector<Vec3>* pts;
    int axis;
    bool operator()(int a, int b) const { return (*pts)[a][axis] < (*pts)[b][axis]; }
  };
  using Less_x_3 = Less;
  using Less_y_3 = Less;
  using Less_z_3 = Less;
  Less less_x_3_object() const { return {pts, 0}; }
  Less less_y_3_object() const { return {pts, 1}; }
  Less less_z_3_object() const { return {pts, 2}; }
};
}  // namespace

// See prefetch_cell in the header.
template <class CellIterator>
void prefetch_vertices(CellIterator c) {
  for (int i = 0; i < 4; ++i) __builtin_prefetch(&*c->vertex(i));
}

struct DelaunayTetrahedralization::Impl {
  DT dt;
  std::vector<DT::Vertex_handle> handle;  // by vertex id
  mutable DT::Cell_handle last_located;    // walk start for the next locate
  mutable std::vector<DT::Cell_handle> numbered;  // by number_cells()

  DT::Vertex_handle at(int id) const { return handle[static_cast<size_t>(id)]; }
};

DelaunayTetrahedralization::DelaunayTetrahedralization() : impl_(std::make_unique<Impl>()) {}
DelaunayTetrahedralization::~DelaunayTetrahedralization() = default;

void DelaunayTetrahedralization::insert(const std::vector<Vec3>& points, int first, const std::atomic<bool>* cancel) {
  std::vector<int> order(points.size() - static_cast<size_t>(first));
  std::iota(order.begin(), order.end(), first);
  // Spatial sort gives CGAL good location hints: O(n log n) overall.
  CGAL::spatial_sort(order.begin(), order.end(), SortByIndex{&points});
  impl_->last_located = DT::Cell_handle();  // insertions may delete it
  std::vector<DT::Cell_handle>().swap(impl_->numbered);
  impl_->handle.resize(points.size());
  DT::Cell_handle hint;
  CancelPoll poll(cancel, 4096);
  size_t done = 0;
  for (int id : order) {
    poll();
    if ((++done & 8191) == 0) set_phase_fraction(static_cast<double>(done) / static_cast<double>(order.size()));
    DT::Vertex_handle v = impl_->dt.insert(to_cgal(points[id]), hint);
    v->info() = id;
    impl_->handle[id] = v;
    hint = v->cell();
  }
}

std::vector<int> DelaunayTetrahedralization::insert_one(const Vec3& p, int id, int hint) {
  DT::Cell_handle start;
  if (hint >= 0) start = impl_->at(hint)->cell();
  impl_->last_located = DT::Cell_handle();  // the insertion may delete it
  std::vector<DT::Cell_handle>().swap(impl_->numbered);
  DT::Vertex_handle v = impl_->dt.insert(to_cgal(p), start);
  v->info() = id;
  if (impl_->handle.size() <= static_cast<size_t>(id)) impl_->handle.resize(id + 1);
  impl_->handle[id] = v;
  return neighbours(id);
}

bool DelaunayTetrahedralization::faces_taken_by(const Vec3& p, std::vector<std::array<int, 3>>& faces,
                                                std::vector<std::array<int, 3>>* boundary) const {
  faces.clear();
  if (boundary) boundary->clear();
  const DT& dt = impl_->dt;
  const CGALPoint q = to_cgal(p);
  DT::Locate_type type;
  int li, lj;
  DT::Cell_handle c = dt.locate(q, type, li, lj, impl_->last_located);
  impl_->last_located = c;
  if (type == DT::VERTEX || type == DT::OUTSIDE_CONVEX_HULL || type == DT::OUTSIDE_AFFINE_HULL) return false;
  std::vector<DT::Facet> inner, around;
  if (boundary)
    dt.find_conflicts(q, c, std::back_inserter(around), CGAL::Emptyset_iterator(), std::back_inserter(inner));
  else
    dt.find_conflicts(q, c, CGAL::Emptyset_iterator(), CGAL::Emptyset_iterator(), std::back_inserter(inner));
  const auto vertices = [&](const DT::Facet& f, std::array<int, 3>& v) {
    bool finite = true;
    for (int k = 0, n = 0; k < 4; ++k) {
      if (k == f.second) continue;
      const DT::Vertex_handle x = f.first->vertex(k);
      const bool infinite = dt.is_infinite(x);
      finite = finite && !infinite;
      v[n++] = infinite ? -1 : x->info();
    }
    return finite;
  };
  std::array<int, 3> v;
  for (const DT::Facet& f : inner)
    if (vertices(f, v)) faces.push_back(v);
  if (boundary)
    for (const DT::Facet& f : around) {
      vertices(f, v);
      boundary->push_back(v);
    }
  return true;
}

void DelaunayTetrahedralization::clear() {
  impl_.reset();  // freed before the new one is made
  impl_ = std::make_unique<Impl>();
}

int DelaunayTetrahedralization::number_of_vertices() const {
  return static_cast<int>(impl_->dt.number_of_vertices());
}

int DelaunayTetrahedralization::dimension() const { return impl_->dt.dimension(); }

std::array<int, 4> DelaunayTetrahedralization::locate(const Vec3& p) const {
  DT::Cell_handle c = impl_->dt.locate(to_cgal(p), impl_->last_located);
  impl_->last_located = c;
  if (impl_->dt.is_infinite(c)) return {-1, -1, -1, -1};
  return {c->vertex(0)->info(), c->vertex(1)->info(), c->vertex(2)->info(), c->vertex(3)->info()};
}

bool DelaunayTetrahedralization::has_facet(int a, int b, int c) const {
  DT::Cell_handle cell;
  int i, j, k;
  return impl_->dt.is_facet(impl_->at(a), impl_->at(b), impl_->at(c), cell, i, j, k);
}

// Calls visit(f, apex) for every side of every tetrahedron (the infinite ones
// included) that is triangle f of `index`, apex the id of the tetrahedron's
// other vertex (-1 when infinite): one sweep in memory order, with the
// vertices of the cell kCellsAhead on fetched early. Inner faces are looked up
// from both sides: telling which side comes first would read the neighbour,
// a cache miss dearer than a lookup.
// With `parts` > 1, only the runs of kRun cells numbered part, part + parts,
// ... in memory order are visited (each part of a sweep on its own thread:
// every thread walks the whole container, which costs little beside the
// look-ups of the cells it keeps).
constexpr size_t kRun = 256;
template <class Visit>
void for_each_facet_side(const DT& dt, const TripleIndex& index, const std::vector<char>& on_surface, Visit visit,
                         size_t part = 0, size_t parts = 1) {
  auto& cells = const_cast<DT&>(dt).tds().cells();  // non-const: its iterators are cell handles
  const auto mine = [&](size_t k) { return k / kRun % parts == part; };
  auto ahead = cells.begin();
  size_t k = 0, k_ahead = 0;
  for (; k_ahead < DelaunayTetrahedralization::kCellsAhead && ahead != cells.end(); ++k_ahead) ++ahead;
  for (auto c = cells.begin(); c != cells.end(); ++c, ++k) {
    if (ahead != cells.end()) {
      if (mine(k_ahead)) prefetch_vertices(ahead);
      ++ahead, ++k_ahead;
    }
    if (!mine(k)) continue;
    int id[4];
    for (int i = 0; i < 4; ++i) id[i] = dt.is_infinite(c->vertex(i)) ? -1 : c->vertex(i)->info();
    for (int i = 0; i < 4; ++i) {
      const std::array<int, 3> face{id[(i + 1) & 3], id[(i + 2) & 3], id[(i + 3) & 3]};
      if (face[0] < 0 || face[1] < 0 || face[2] < 0) continue;
      if (!on_surface[face[0]] || !on_surface[face[1]] || !on_surface[face[2]]) continue;
      const int f = index.find(face);
      if (f >= 0) visit(f, id[i]);
    }
  }
}

std::vector<char> DelaunayTetrahedralization::has_facets(const std::vector<Triangle>& triangles) const {
  const TripleIndex index(triangles, [](const Triangle& t) { return t.v; });
  const std::vector<char> on_surface = surface_vertex_flags(impl_->handle.size(), triangles);
  // On all threads, each marking its own table (a facet is found from both
  // sides, maybe by two threads): a tenth of a surface-only run on one.
  const size_t parts = impl_->dt.number_of_cells() < 8 * kRun ? 1 : static_cast<size_t>(std::max(1, thread_count()));
  std::vector<std::vector<char>> found(parts, std::vector<char>(triangles.size(), 0));
  for_each_chunk(static_cast<long>(parts), 1, [&](long part, long, long) {
    std::vector<char>& mine = found[static_cast<size_t>(part)];
    for_each_facet_side(
        impl_->dt, index, on_surface, [&](int f, int) { mine[f] = 1; }, static_cast<size_t>(part), parts);
  });
  for (size_t p = 1; p < parts; ++p)
    for (size_t f = 0; f < triangles.size(); ++f) found[0][f] |= found[p][f];
  std::vector<char> out(triangles.size());
  for (size_t f = 0; f < triangles.size(); ++f) out[f] = found[0][index.find(triangles[f].v)];
  return out;
}

std::array<int, 2> DelaunayTetrahedralization::facet_apexes(int a, int b, int c) const {
  DT::Cell_handle cell;
  int i, j, k;
  if (!impl_->dt.is_facet(impl_->at(a), impl_->at(b), impl_->at(c), cell, i, j, k)) return {-2, -2};
  const int opposite = 6 - i - j - k;
  const DT::Cell_handle across = cell->neighbor(opposite);
  auto id_of = [&](DT::Vertex_handle v) { return impl_->dt.is_infinite(v) ? -1 : v->info(); };
  return {id_of(cell->vertex(opposite)), id_of(across->vertex(across->index(cell)))};
}

std::vector<std::array<int, 2>> DelaunayTetrahedralization::facet_apexes(const std::vector<Triangle>& triangles) const {
  const DT& dt = impl_->dt;
  std::vector<std::array<int, 2>> out(triangles.size(), {-2, -2});
  if (dt.number_of_cells() > 60 * triangles.size()) {
    for (size_t f = 0; f < triangles.size(); ++f) out[f] = facet_apexes(triangles[f].v[0], triangles[f].v[1], triangles[f].v[2]);
    return out;
  }
  const TripleIndex index(triangles, [](const Triangle& t) { return t.v; });
  std::vector<char> seen(triangles.size(), 0);
  for_each_facet_side(impl_->dt, index, surface_vertex_flags(impl_->handle.size(), triangles), [&](int f, int apex) {
    if (seen[f] < 2) out[f][seen[f]++] = apex;
  });
  return out;
}

bool DelaunayTetrahedralization::has_edge(int a, int b) const {
  DT::Cell_handle cell;
  int i, j;
  return impl_->dt.is_edge(impl_->at(a), impl_->at(b), cell, i, j);
}

std::vector<int> DelaunayTetrahedralization::neighbours(int id) const {
  std::vector<DT::Vertex_handle> adjacent;
  impl_->dt.finite_adjacent_vertices(impl_->at(id), std::back_inserter(adjacent));
  std::vector<int> ids;
  ids.reserve(adjacent.size());
  for (auto v : adjacent) ids.push_back(v->info());
  std::sort(ids.begin(), ids.end());
  return ids;
}

int DelaunayTetrahedralization::number_cells() const {
  const DT& dt = impl_->dt;
  auto& numbered = impl_->numbered;
  numbered.clear();
  numbered.reserve(dt.number_of_finite_cells());
  for (auto c : dt.all_cell_handles()) c->info().value = -1;
  for (auto c : dt.finite_cell_handles()) {
    c->info().value = static_cast<int>(numbered.size());
    numbered.push_back(c);
  }
  return static_cast<int>(numbered.size());
}

void DelaunayTetrahedralization::label_cells(const std::vector<int>& labels) {
  auto& numbered = impl_->numbered;
  if (labels.size() != numbered.size()) throw std::logic_error("label_cells: one label per numbered tetrahedron");
  for (auto c : impl_->dt.all_cell_handles()) c->info().value = 0;  // the infinite ones keep it
  for (size_t t = 0; t < numbered.size(); ++t) numbered[t]->info().value = labels[t];
  std::vector<DT::Cell_handle>().swap(numbered);
}

int DelaunayTetrahedralization::label_at(const Vec3& p) const {
  DT::Cell_handle c = impl_->dt.locate(to_cgal(p), impl_->last_located);
  impl_->last_located = c;
  return c->info().value;
}

void DelaunayTetrahedralization::label_star(int vertex, int label) {
  std::vector<DT::Cell_handle> star;
  impl_->dt.incident_cells(impl_->at(vertex), std::back_inserter(star));
  for (auto c : star) c->info().value = impl_->dt.is_infinite(c) ? 0 : label;
}

void DelaunayTetrahedralization::label_new_cells(int first, const std::vector<int>& vertex_region) {
  const DT& dt = impl_->dt;
  for (auto c : dt.all_cell_handles()) {
    if (c->info().value >= 0) continue;
    if (dt.is_infinite(c)) {
      c->info().value = 0;
      continue;
    }
    int label = -1;
    for (int i = 0; i < 4 && label < 0; ++i) {
      const int id = c->vertex(i)->info();
      if (id >= first) label = vertex_region.at(static_cast<size_t>(id - first));
    }
    if (label < 0) throw std::logic_error("label_new_cells: a new tetrahedron has no new vertex");
    c->info().value = label;
  }
}

bool DelaunayTetrahedralization::relabel_changed_cells(const Mesh& surface,
                                                       const std::vector<std::array<int, 3>>& changed) {
  DT& dt = impl_->dt;
  for (const auto& k : changed) {
    if (std::max({k[0], k[1], k[2]}) >= static_cast<int>(impl_->handle.size())) continue;
    DT::Cell_handle c;
    int i, j, l;
    if (!dt.is_facet(impl_->at(k[0]), impl_->at(k[1]), impl_->at(k[2]), c, i, j, l)) continue;
    c->info().value = -1;
    c->neighbor(6 - i - j - l)->info().value = -1;
  }
  const TripleIndex facet_of(surface.triangles, [](const Triangle& t) { return t.v; });
  std::vector<DT::Cell_handle> pending;
  for (auto c : dt.all_cell_handles()) {
    if (c->info().value >= 0) continue;
    if (dt.is_infinite(c)) c->info().value = 0;  // beyond the hull: the exterior, as label_cells has it
    else pending.push_back(c);
  }
  // The label of finite cell c from its face i, -1 when that tells nothing yet.
  const auto label_from = [&](const DT::Cell_handle& c, int i) {
    const std::array<int, 3> face = {c->vertex((i + 1) & 3)->info(), c->vertex((i + 2) & 3)->info(),
                                     c->vertex((i + 3) & 3)->info()};
    const int f = facet_of.find(face);
    if (f >= 0) {
      const Triangle& t = surface.triangles[static_cast<size_t>(f)];
      const auto& p = surface.points;
      const int side = orientation(p[t.v[0]], p[t.v[1]], p[t.v[2]], p[c->vertex(i)->info()]);
      return side > 0 ? t.front : side < 0 ? t.back : -1;
    }
    return c->neighbor(i)->info().value;
  };
  while (!pending.empty()) {
    std::vector<DT::Cell_handle> left;
    for (const DT::Cell_handle& c : pending) {
      int label = -1;
      for (int i = 0; i < 4 && label < 0; ++i) label = label_from(c, i);
      if (label >= 0) c->info().value = label;
      else left.push_back(c);
    }
    if (left.size() == pending.size()) return false;
    pending = std::move(left);
  }
  return true;
}

std::vector<Tetrahedron> DelaunayTetrahedralization::labelled_cells(int* exterior) const {
  // Reserved exactly: the caller keeps the vector to the end of the run.
  size_t labelled = 0;
  for (auto c : impl_->dt.finite_cell_handles()) labelled += c->info().value > 0;
  if (exterior) *exterior = static_cast<int>(impl_->dt.number_of_finite_cells() - labelled);
  std::vector<Tetrahedron> out;
  out.reserve(labelled);
  for (auto c : impl_->dt.finite_cell_handles()) {
    if (c->info().value < 0) throw std::logic_error("labelled_cells: a tetrahedron has no label");
    if (c->info().value > 0)
      out.push_back({{c->vertex(0)->info(), c->vertex(1)->info(), c->vertex(2)->info(), c->vertex(3)->info()}, c->info().value});
  }
  return out;
}

std::array<int, 4> DelaunayTetrahedralization::cell(int t) const {
  // CGAL's finite cells are positively oriented (orientation(p0..p3) > 0).
  const DT::Cell_handle c = impl_->numbered[static_cast<size_t>(t)];
  return {c->vertex(0)->info(), c->vertex(1)->info(), c->vertex(2)->info(), c->vertex(3)->info()};
}

void DelaunayTetrahedralization::prefetch_cell(int t) const {
  if (static_cast<size_t>(t) < impl_->numbered.size()) prefetch_vertices(impl_->numbered[static_cast<size_t>(t)]);
}

int DelaunayTetrahedralization::cell_across(int t, int i) const {
  return impl_->numbered[static_cast<size_t>(t)]->neighbor(i)->info().value;
}

std::vector<int> DelaunayTetrahedralization::joined_cells(const std::vector<std::uint8_t>& walls) const {
  const auto& numbered = impl_->numbered;
  const size_t n = numbered.size();
  DisjointSets sets(n);
  for (size_t t = 0; t < n; ++t) {
    if (t + kCellsAhead < n) {
      const DT::Cell_handle ahead = numbered[t + kCellsAhead];
      for (int i = 0; i < 4; ++i) __builtin_prefetch(&*ahead->neighbor(i));
    }
    const DT::Cell_handle c = numbered[t];
    const std::uint8_t wall = walls[t];
    for (int i = 0; i < 4; ++i) {
      if (wall & (1u << i)) continue;
      const int u = c->neighbor(i)->info().value;
      if (u <= static_cast<int>(t)) continue;  // infinite, or joined from u's side
      sets.join(static_cast<int>(t), u);
    }
  }
  return std::move(sets).roots();
}

std::vector<std::array<int, 2>> DelaunayTetrahedralization::hull_faces() const {
  const DT& dt = impl_->dt;
  std::vector<std::array<int, 2>> out;
  for (auto c : dt.all_cell_handles()) {
    if (!dt.is_infinite(c)) continue;
    const DT::Cell_handle inside = c->neighbor(c->index(dt.infinite_vertex()));
    out.push_back({inside->info().value, inside->index(c)});
  }
  return out;
}

}  // namespace vd
