#include "volume/interior_vertices.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <random>
#include <unordered_map>

#include "geometry/cell_key.h"
#include "geometry/point_grid.h"
#include "mesh/cancel.h"
#include "mesh/progress.h"
#include "surface/face_patches.h"

namespace vd {
namespace {

// The bounding box of facet t.
Box facet_box(const Mesh& m, const Triangle& t) {
  Box b{m.points[t.v[0]], m.points[t.v[0]]};
  for (int v : t.v)
    for (int i = 0; i < 3; ++i) b.lo[i] = std::min(b.lo[i], m.points[v][i]), b.hi[i] = std::max(b.hi[i], m.points[v][i]);
  return b;
}

// Facets hashed into grids by their bounding boxes, to find the facets near
// a point. Most points asked about are deep inside, their cells empty: a bit
// per hashed cell (16 bits per occupied cell, 6 % false hits) answers them
// without the hash map, whose bucket and node reads were four fifths of a
// candidate's test on the 6.6M-tetrahedron box.
// A facet goes on the finest of grids 4^level times the mean edge whose cells
// it spans at most kSpan of along each axis: on one grid of the mean edge,
// the far field's big facets in gmsh_simple_plane.brep were each listed in
// the many cells of the aircraft's scale they cover (0.7 s to build the
// grid, 2 % of the run; the phase 2.4-2.9 -> 1.5 s, its peak 330 -> 200 MiB).
class FacetGrid {
 public:
  FacetGrid(const Mesh& m, double cell) : m_(m), finest_(cell) {
    for (size_t f = 0; f < m.triangles.size(); ++f) {
      const Box box = facet_box(m, m.triangles[f]);
      size_t level = 0;
      double side = finest_;
      auto a = cell_coords(box.lo, side), b = cell_coords(box.hi, side);
      while (b[0] - a[0] >= kSpan || b[1] - a[1] >= kSpan || b[2] - a[2] >= kSpan) {
        side *= 4, ++level;
        a = cell_coords(box.lo, side), b = cell_coords(box.hi, side);
      }
      if (levels_.size() <= level) levels_.resize(level + 1);
      for (long k = a[2]; k <= b[2]; ++k)
        for (long j = a[1]; j <= b[1]; ++j)
          for (long i = a[0]; i <= b[0]; ++i) levels_[level].cells[pack_cell({i, j, k})].push_back(static_cast<int>(f));
    }
    double side = finest_;
    for (Level& level : levels_) {
      level.side = side;
      side *= 4;
      int log2_bits = 6;
      while ((std::uint64_t(1) << log2_bits) < 16 * level.cells.size()) ++log2_bits;
      level.occupied.assign((std::uint64_t(1) << log2_bits) / 64, 0);
      level.shift = 64 - log2_bits;
      for (const auto& cell : level.cells) {
        const std::uint64_t b = level.bit_of(cell.first);
        level.occupied[b >> 6] |= std::uint64_t(1) << (b & 63);
      }
    }
  }
  // Is any facet closer to p than r?
  bool any_within(const Vec3& p, double r) const {
    for (const Level& level : levels_) {
      if (level.cells.empty()) continue;
      const auto a = cell_coords(p - Vec3{r, r, r}, level.side), b = cell_coords(p + Vec3{r, r, r}, level.side);
      for (long k = a[2]; k <= b[2]; ++k)
        for (long j = a[1]; j <= b[1]; ++j)
          for (long i = a[0]; i <= b[0]; ++i) {
            const std::uint64_t packed = pack_cell({i, j, k}), b = level.bit_of(packed);
            if (!(level.occupied[b >> 6] >> (b & 63) & 1)) continue;
            auto it = level.cells.find(packed);
            if (it == level.cells.end()) continue;
            for (int f : it->second) {
              const auto& t = m_.triangles[f].v;
              if (point_triangle_distance(p, m_.points[t[0]], m_.points[t[1]], m_.points[t[2]]) < r) return true;
            }
          }
    }
    return false;
  }

 private:
  // Cells a facet may span along an axis on its grid: the mean facet spans
  // one or two on the finest.
  static constexpr long kSpan = 4;
  struct Level {
    double side = 1;
    std::unordered_map<std::uint64_t, std::vector<int>> cells;
    std::vector<std::uint64_t> occupied;
    int shift = 58;
    // Fibonacci hashing: the top bits of the product.
    std::uint64_t bit_of(std::uint64_t packed) const { return packed * 0x9E3779B97F4A7C15ull >> shift; }
  };
  const Mesh& m_;
  double finest_;
  std::vector<Level> levels_;
};

class Acceptor {
 public:
  Acceptor(const Mesh& m, const SizeField& size, const std::function<int(const Vec3&)>& region_at,
           const InteriorOptions& o, InteriorStats& stats, double facet_cell)
      : size_(size), region_at_(region_at), o_(o), stats_(stats), facets_(m, facet_cell), rng_(o.seed),
        poll_(o.cancel, 256) {
    grid_.build(m.points);
  }

  // Tries p; `expected` region (>0) or -1 for any non-exterior region.
  // `known` (>0) is p's region when the caller knows it (the lattice in a
  // box no facet reaches), so that p need not be located.
  void offer(Vec3 p, int expected, int known = -1) {
    poll_();
    ++stats_.candidates;
    const double h = size_.at(p);
    std::normal_distribution<double> g(0.0, o_.jitter * h / std::sqrt(3.0));
    Vec3 shift{g(rng_), g(rng_), g(rng_)};
    // At most half the surface gap: a known region stays true, as a point
    // jittered across a facet lands nearer to it than the gap.
    const double longest = 0.5 * o_.min_surface_gap * h, length = norm(shift);
    if (length > longest) shift = (longest / length) * shift;
    p = p + shift;
    // The vertex gap before the region: it costs less than a point location.
    if (grid_.any_in_ball(p, o_.min_vertex_gap * h)) {
      ++stats_.rejected_near_vertex;
      return;
    }
    const int r = known > 0 ? known : region_at_(p);
    if (r <= 0 || (expected > 0 && r != expected)) {
      ++stats_.rejected_outside;
      return;
    }
    if (facets_.any_within(p, o_.min_surface_gap * h)) {
      ++stats_.rejected_near_surface;
      return;
    }
    if (o_.takes_a_facet && o_.takes_a_facet(p)) {
      ++stats_.rejected_taking_a_facet;
      return;
    }
    grid_.update(grid_.size(), p);
    accepted_.push_back(p);
    regions_.push_back(r);
  }
  std::vector<Vec3>& accepted() { return accepted_; }
  std::vector<int>& regions() { return regions_; }

 private:
  const SizeField& size_;
  const std::function<int(const Vec3&)>& region_at_;
  const InteriorOptions& o_;
  InteriorStats& stats_;
  FacetGrid facets_;
  PointGrid grid_;
  std::vector<Vec3> accepted_;
  std::vector<int> regions_;  // of each accepted point
  std::mt19937_64 rng_;
  CancelPoll poll_;
};

// The lattice keys offered so far: open addressing over one array (a key
// is at most 63 bits, so all ones marks an empty slot). std::unordered_set's
// node per key and its rehashes were most of the octree walk's time.
class KeySet {
 public:
  // True when k was not in the set (it is now).
  bool insert(std::uint64_t k) {
    if (2 * (count_ + 1) > slots_.size()) grow();
    for (size_t i = slot_of(k);; i = (i + 1) & (slots_.size() - 1)) {
      if (slots_[i] == k) return false;
      if (slots_[i] == kEmpty) {
        slots_[i] = k;
        ++count_;
        return true;
      }
    }
  }

 private:
  static constexpr std::uint64_t kEmpty = ~std::uint64_t(0);
  size_t slot_of(std::uint64_t k) const { return static_cast<size_t>(k * 0x9E3779B97F4A7C15ull >> shift_); }
  void grow() {
    log2_slots_ = slots_.empty() ? 10 : log2_slots_ + 1;
    std::vector<std::uint64_t> old(size_t(1) << log2_slots_, kEmpty);
    old.swap(slots_);
    shift_ = 64 - log2_slots_;
    count_ = 0;
    for (std::uint64_t k : old)
      if (k != kEmpty) insert(k);
  }
  std::vector<std::uint64_t> slots_;
  size_t count_ = 0;
  int log2_slots_ = 0, shift_ = 64;
};

// Octree leaves no larger than 2 h at their centre; each leaf offers its
// centre and its twelve edge mid-points, an FCC lattice of spacing side/sqrt(2):
// between 0.71 h and 1.41 h, within sqrt(2) of h either way. With leaves up to
// sqrt(2) h (spacing 0.5 h to h) the vertex-gap test (0.65 h) thinned the finer
// lattices into irregular subsets full of flat tetrahedra: a unit sphere at
// size 0.0395 had 919k tetrahedra, 140k of them slivers before the sliver
// pass (24.5 s in all), against 494k and 5.8k at size 0.05; now 540k and 10k
// (3.8 s).
//
// Nodes and points live on an integer lattice (the bounding cube's side is
// 2^(depth+1) units, the root's twice that), so an edge mid-point shared by
// up to four leaves is the same key from each and is offered once (21 bits
// per axis: depth at most 18): the copies were two thirds of the candidates.
//
// Each node carries the facets whose bounding boxes meet it. A node that
// none meets lies in one region, found by locating its centre once: outside
// the model the whole subtree is skipped (half the bounding cube of a
// sphere), inside it its points need no location of their own.
class OctreeLattice {
 public:
  using Offer = std::function<void(const Vec3& p, int known_region)>;
  OctreeLattice(const Mesh& m, const Vec3& lo, double side, const SizeField& size, const InteriorOptions& o,
                const std::function<int(const Vec3&)>& region_at, const Offer& offer)
      : lo_(lo), depth_(std::clamp(o.max_octree_depth, 0, 18)), size_(size), region_at_(region_at), offer_(offer) {
    const std::int64_t units = std::int64_t(1) << (depth_ + 1);
    unit_ = side / static_cast<double>(units);
    boxes_.reserve(m.triangles.size());
    std::vector<int> all(m.triangles.size());
    for (size_t f = 0; f < m.triangles.size(); ++f) {
      boxes_.push_back(facet_box(m, m.triangles[f]));
      all[f] = static_cast<int>(f);
    }
    // The root is twice the bounding cube, so that the lattice, shorter
    // along x, still spans it; the leaves keep their sizes (depth counts
    // from the bounding cube, hence -1 here).
    visit({0, 0, 0}, 2 * units, -1, all, -1);
  }

 private:
  using Key = std::array<std::int64_t, 3>;
  // The lattice is stretched by -3 %, 0 and +3 % along x, y and z. A cubic
  // FCC lattice has six vertices on the sphere of each octahedral hole, and
  // the jitter split some holes with a flat tetrahedron across the middle:
  // 519 slivers deep inside the 861k-tetrahedron box. Stretched, a hole's
  // three diagonals differ by 3 % in length, more than the jitter (1 %)
  // moves them, so every hole splits into four tetrahedra around the shortest
  // (12 slivers deep inside; 9,416 -> 7,171 in all, with those near the
  // surface; 6,192 -> 4,780 on the 159k box, 10,000 -> 9,939 on the 507k
  // sphere, whose lattice is cut up by the curved surface).
  static constexpr double kStretch = 0.03;
  Vec3 at(const Key& k) const {
    return lo_ + unit_ * Vec3{double(k[0]) * (1 - kStretch), double(k[1]), double(k[2]) * (1 + kStretch)};
  }
  void offer(const Key& k, int region) {
    const std::uint64_t packed = (std::uint64_t(k[0]) << 42) | (std::uint64_t(k[1]) << 21) | std::uint64_t(k[2]);
    if (seen_.insert(packed)) offer_(at(k), region);
  }
  // Facets of `from` whose boxes meet the closed node box.
  std::vector<int> meeting(const std::vector<int>& from, const Key& lo, std::int64_t side) const {
    const Vec3 a = at(lo), b = at({lo[0] + side, lo[1] + side, lo[2] + side});
    std::vector<int> out;
    for (int f : from) {
      const Box& x = boxes_[static_cast<size_t>(f)];
      if (x.lo.x <= b.x && x.hi.x >= a.x && x.lo.y <= b.y && x.hi.y >= a.y && x.lo.z <= b.z && x.hi.z >= a.z)
        out.push_back(f);
    }
    return out;
  }
  // `region` > -1: every point of the node is in that region.
  void visit(const Key& lo, std::int64_t side, int depth, const std::vector<int>& facets, int region) {
    const std::int64_t half = side / 2;
    const Key centre{lo[0] + half, lo[1] + half, lo[2] + half};
    if (region < 0 && facets.empty()) {
      region = region_at_(at(centre));
      if (region == 0) {
        done(side);
        return;
      }
    }
    if (static_cast<double>(side) * unit_ > 2.0 * size_.at(at(centre)) && depth < depth_) {
      for (int k = 0; k < 2; ++k)
        for (int j = 0; j < 2; ++j)
          for (int i = 0; i < 2; ++i) {
            const Key child{lo[0] + i * half, lo[1] + j * half, lo[2] + k * half};
            visit(child, half, depth + 1, region < 0 ? meeting(facets, child, half) : facets, region);
          }
      return;
    }
    done(side);
    offer(centre, region);
    for (int axis = 0; axis < 3; ++axis) {
      const int u = (axis + 1) % 3, v = (axis + 2) % 3;
      for (int a = 0; a < 2; ++a)
        for (int b = 0; b < 2; ++b) {
          Key p = lo;
          p[axis] += half;
          p[u] += a * side;
          p[v] += b * side;
          offer(p, region);
        }
    }
  }

  // A leaf or a skipped node of `side` units is finished: the share of the
  // root's volume done so far is the phase's progress.
  void done(std::int64_t side) {
    const double s = static_cast<double>(side) / static_cast<double>(std::int64_t(1) << (depth_ + 1));
    volume_done_ += s * s * s;  // of the bounding cube, which is visited first
    if ((++leaves_ & 1023) == 0) set_phase_fraction(std::min(1.0, volume_done_));
  }

  Vec3 lo_;
  int depth_;
  double volume_done_ = 0;
  long leaves_ = 0;
  double unit_ = 1;
  const SizeField& size_;
  const std::function<int(const Vec3&)>& region_at_;
  const Offer& offer_;
  std::vector<Box> boxes_;
  KeySet seen_;
};

// The side of the octree's bounding cube. With --size H, the smallest
// sqrt(2) H 2^k that holds the model, so that the leaves where the size is
// H are sqrt(2) H and their lattice's spacing is H. Sized by the bounding box
// alone, the spacing fell anywhere between 0.71 H and 1.41 H, and sizes a
// hair either side of 2^-k times the box gave very different meshes (0.062
// and 0.0632 on a unit cube: 12,167 and 3,566 interior vertices). Without a
// size the field varies, and no one cube fits it.
double lattice_cube_side(double bounding_side, double requested_size) {
  if (!(requested_size > 0)) return bounding_side;
  double side = std::sqrt(2.0) * requested_size;
  while (side < bounding_side) side *= 2;
  while (side / 2 >= bounding_side) side /= 2;
  return side;
}

}  // namespace

double point_triangle_distance(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  // Closest point by regions of the triangle (Voronoi regions of its features).
  const Vec3 ab = b - a, ac = c - a, ap = p - a;
  const double d1 = dot(ab, ap), d2 = dot(ac, ap);
  if (d1 <= 0 && d2 <= 0) return norm(ap);
  const Vec3 bp = p - b;
  const double d3 = dot(ab, bp), d4 = dot(ac, bp);
  if (d3 >= 0 && d4 <= d3) return norm(bp);
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return norm(p - (a + (d1 / (d1 - d3)) * ab));
  const Vec3 cp = p - c;
  const double d5 = dot(ab, cp), d6 = dot(ac, cp);
  if (d6 >= 0 && d5 <= d6) return norm(cp);
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return norm(p - (a + (d2 / (d2 - d6)) * ac));
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0)
    return norm(p - (b + ((d4 - d3) / ((d4 - d3) + (d5 - d6))) * (c - b)));
  const double denom = 1.0 / (va + vb + vc);
  return norm(p - (a + (vb * denom) * ab + (vc * denom) * ac));
}

std::vector<Vec3> generate_interior_vertices(const Mesh& m, const SizeField& size,
                                             const std::function<int(const Vec3&)>& region_at,
                                             const InteriorOptions& o, InteriorStats& stats,
                                             std::vector<int>* regions) {
  if (m.triangles.empty()) return {};
  double mean_edge = 0;
  for (const Triangle& t : m.triangles) mean_edge += norm(m.points[t.v[1]] - m.points[t.v[0]]);
  mean_edge /= m.triangles.size();
  Acceptor acceptor(m, size, region_at, o, stats, std::max(mean_edge, 1e-12));

  // Stage 1: offsets from the facet barycentres, into each non-exterior side.
  for (const Triangle& t : m.triangles) {
    const Vec3 c = (1.0 / 3.0) * (m.points[t.v[0]] + m.points[t.v[1]] + m.points[t.v[2]]);
    const double hf = (norm(m.points[t.v[1]] - m.points[t.v[0]]) + norm(m.points[t.v[2]] - m.points[t.v[1]]) +
                       norm(m.points[t.v[0]] - m.points[t.v[2]])) / 3.0;
    const double d = o.offset * std::min(hf, size.at(c));
    const Vec3 n = facet_normal(m.points, t);
    if (t.front > 0) acceptor.offer(c + d * n, t.front);
    if (t.back > 0) acceptor.offer(c - d * n, t.back);
  }
  stats.offset_points = static_cast<long>(acceptor.accepted().size());

  // Stage 2: the octree lattice over the bounding cube.
  Vec3 lo = m.points[m.triangles[0].v[0]], hi = lo;
  for (const Triangle& t : m.triangles)
    for (int v : t.v)
      for (int i = 0; i < 3; ++i) lo[i] = std::min(lo[i], m.points[v][i]), hi[i] = std::max(hi[i], m.points[v][i]);
  const double side = lattice_cube_side(std::max({hi.x - lo.x, hi.y - lo.y, hi.z - lo.z}) * 1.001, size.requested());
  const OctreeLattice::Offer offer = [&](const Vec3& p, int region) { acceptor.offer(p, -1, region); };
  OctreeLattice(m, lo, side, size, o, region_at, offer);
  stats.lattice_points = static_cast<long>(acceptor.accepted().size()) - stats.offset_points;
  if (regions) *regions = std::move(acceptor.regions());
  return std::move(acceptor.accepted());
}

}  // namespace vd
