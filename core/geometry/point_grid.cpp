#include "geometry/point_grid.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "geometry/predicates.h"

namespace vd {
namespace {

// Cells per axis never exceed this, so that a query box spanning the whole
// set stays a bounded loop even when the points are very unevenly spread.
constexpr double kMaxCellsPerAxis = 1024;

double largest_extent(const Vec3& lo, const Vec3& hi) {
  return std::max({hi.x - lo.x, hi.y - lo.y, hi.z - lo.z, 0.0});
}

// Average spacing of n points spread over the box: the edge of the cube each
// point would own. Flat or thin sets are measured as if they had a small
// thickness, so the cells do not collapse to nothing.
double average_spacing(const Vec3& lo, const Vec3& hi, int n) {
  const double extent = largest_extent(lo, hi);
  if (!(extent > 0) || !std::isfinite(extent)) return 1;
  const double floor_extent = extent / std::cbrt(std::max(n, 1));
  double volume = 1;
  for (int i = 0; i < 3; ++i) volume *= std::max(hi[i] - lo[i], floor_extent);
  return std::cbrt(volume / std::max(n, 1));
}

}  // namespace

void PointGrid::build(const std::vector<Vec3>& points) {
  position_ = points;
  rebuild();
}

void PointGrid::update(int id, const Vec3& p) {
  if (id < 0) return;
  if (static_cast<size_t>(id) < position_.size()) {
    remove_from_cell(id);
    position_[static_cast<size_t>(id)] = p;
  } else {
    // Appended: ids grow one by one, but tolerate a gap rather than index
    // out of range (the missing ones sit at p until updated).
    const size_t first_new = position_.size();
    position_.resize(static_cast<size_t>(id) + 1, p);
    next_.resize(position_.size(), -1);
    for (size_t i = first_new; i + 1 < position_.size(); ++i) {
      grow_bounds(position_[i]);
      insert_into_cell(static_cast<int>(i));
    }
  }
  grow_bounds(p);
  if (needs_rebuild()) {
    rebuild();
  } else {
    insert_into_cell(id);
  }
}

PointGrid::CellKey PointGrid::cell_of(const Vec3& p) const {
  CellKey key;
  for (int i = 0; i < 3; ++i) {
    double c = std::floor((p[i] - origin_[i]) / cell_size_);
    if (!(c == c)) c = 0;  // NaN coordinates all land in one cell
    key[static_cast<size_t>(i)] = static_cast<std::int64_t>(std::clamp(c, 0.0, static_cast<double>(dims_[i] - 1)));
  }
  return key;
}

std::array<std::int64_t, 3> PointGrid::fine_key(const CellKey& key, const Vec3& p) const {
  std::array<std::int64_t, 3> sub;
  const double fine = cell_size_ / kFine;
  for (int i = 0; i < 3; ++i) {
    const double corner = origin_[i] + static_cast<double>(key[static_cast<size_t>(i)]) * cell_size_;
    double c = std::floor((p[i] - corner) / fine);
    if (!(c == c)) c = 0;
    sub[static_cast<size_t>(i)] = static_cast<std::int64_t>(std::clamp(c, 0.0, static_cast<double>(kFine - 1)));
  }
  return sub;
}

size_t PointGrid::fine_index(const CellKey& key, const Vec3& p) const {
  const auto sub = fine_key(key, p);
  return static_cast<size_t>((sub[0] * kFine + sub[1]) * kFine + sub[2]);
}

void PointGrid::list(std::vector<int>& head, std::vector<int>& tail, size_t at, int id) {
  next_[static_cast<size_t>(id)] = -1;
  if (head[at] < 0) head[at] = id;
  else next_[static_cast<size_t>(tail[at])] = id;
  tail[at] = id;
}

void PointGrid::unlist(std::vector<int>& head, std::vector<int>& tail, size_t at, int id) {
  int before = -1, now = head[at];
  while (now >= 0 && now != id) before = now, now = next_[static_cast<size_t>(now)];
  if (now < 0) return;  // not listed
  const int after = next_[static_cast<size_t>(id)];
  if (before < 0) head[at] = after;
  else next_[static_cast<size_t>(before)] = after;
  if (tail[at] == id) tail[at] = before;
}

void PointGrid::split_cell(const CellKey& key, size_t cell) {
  fine_of_[cell] = static_cast<int>(fine_.size());
  fine_.push_back({std::vector<int>(kFine * kFine * kFine, -1), std::vector<int>(kFine * kFine * kFine, -1)});
  FineCells& sub = fine_.back();
  for (int id = head_[cell], next; id >= 0; id = next) {
    next = next_[static_cast<size_t>(id)];
    list(sub.head, sub.tail, fine_index(key, position(id)), id);
  }
  head_[cell] = tail_[cell] = -1;
}

void PointGrid::insert_into_cell(int id) {
  const Vec3& p = position(id);
  for (int i = 0; i < 3; ++i)
    if (!(p[i] >= origin_[i] && p[i] < origin_[i] + static_cast<double>(dims_[i]) * cell_size_)) {
      ++outside_;
      break;
    }
  const CellKey key = cell_of(p);
  const size_t cell = index_of(key);
  if (count_[cell]++ == 0) ++occupied_;
  if (fine_of_[cell] >= 0) {
    FineCells& sub = fine_[static_cast<size_t>(fine_of_[cell])];
    list(sub.head, sub.tail, fine_index(key, p), id);
    return;
  }
  list(head_, tail_, cell, id);
  if (count_[cell] > kCrowdedCell) split_cell(key, cell);
}

void PointGrid::remove_from_cell(int id) {
  const CellKey key = cell_of(position(id));
  const size_t cell = index_of(key);
  if (count_[cell] == 0) return;
  if (fine_of_[cell] >= 0) {
    FineCells& sub = fine_[static_cast<size_t>(fine_of_[cell])];
    unlist(sub.head, sub.tail, fine_index(key, position(id)), id);
  } else {
    unlist(head_, tail_, cell, id);
  }
  if (--count_[cell] == 0) --occupied_;
}

void PointGrid::grow_bounds(const Vec3& p) {
  if (!has_bounds_) {
    lower_ = upper_ = p;
    has_bounds_ = true;
    return;
  }
  for (int i = 0; i < 3; ++i) {
    lower_[i] = std::min(lower_[i], p[i]);
    upper_[i] = std::max(upper_[i], p[i]);
  }
}

bool PointGrid::needs_rebuild() const {
  // The cells were sized for built_for_count_ points over built_for_extent_;
  // far more points per cell, or a set that spread far beyond, makes queries
  // slow (too many points per cell, too many cells per axis, or too many
  // points crowded into the border cells).
  if (size() >= 2 * std::max(built_for_count_, 4)) return true;
  if (outside_ > std::max<long>(16, built_for_count_ / 16)) return true;
  const double extent = largest_extent(lower_, upper_);
  return extent > 2 * built_for_extent_ && extent / cell_size_ > kMaxCellsPerAxis / 4;
}

void PointGrid::rebuild() {
  has_bounds_ = false;
  for (const Vec3& p : position_) grow_bounds(p);
  if (!has_bounds_) lower_ = upper_ = Vec3{0, 0, 0};
  origin_ = lower_;
  const double extent = largest_extent(lower_, upper_);
  cell_size_ = average_spacing(lower_, upper_, size());
  if (extent > 0 && std::isfinite(extent))
    cell_size_ = std::max(cell_size_, extent / kMaxCellsPerAxis);
  if (!(cell_size_ > 0) || !std::isfinite(cell_size_)) cell_size_ = 1;
  size_t cells = 1;
  for (int i = 0; i < 3; ++i) {
    const double span = std::floor((upper_[i] - lower_[i]) / cell_size_) + 1;
    dims_[i] = static_cast<std::int64_t>(std::clamp(span == span ? span : 1.0, 1.0, kMaxCellsPerAxis + 1));
    cells *= static_cast<size_t>(dims_[i]);
  }
  head_.assign(cells, -1);
  tail_.assign(cells, -1);
  count_.assign(cells, 0);
  fine_of_.assign(cells, -1);
  fine_.clear();
  next_.assign(position_.size(), -1);
  occupied_ = 0;
  outside_ = 0;
  built_for_count_ = size();
  built_for_extent_ = extent;
  for (int id = 0; id < size(); ++id) insert_into_cell(id);
}

template <class Stop>
bool PointGrid::find_in_box(const Vec3& lo_in, const Vec3& hi_in, Stop&& stop) const {
  if (position_.empty()) return false;
  // Clamp to the indexed points: a query box far larger than the set must
  // not turn into a loop over empty cells.
  Vec3 lo, hi;
  for (int i = 0; i < 3; ++i) {
    lo[i] = std::max(lo_in[i], lower_[i]);
    hi[i] = std::min(hi_in[i], upper_[i]);
    if (!(lo[i] <= hi[i])) return false;
  }
  const auto inside = [&](const Vec3& p) {
    return p.x >= lo.x && p.x <= hi.x && p.y >= lo.y && p.y <= hi.y && p.z >= lo.z &&
           p.z <= hi.z;
  };
  const CellKey first = cell_of(lo), last = cell_of(hi);
  double cell_count = 1;
  for (size_t i = 0; i < 3; ++i) cell_count *= static_cast<double>(last[i] - first[i] + 1);
  if (cell_count > static_cast<double>(occupied_)) {
    // More cells in the range than occupied cells: scanning the points is cheaper.
    for (int id = 0; id < size(); ++id)
      if (inside(position(id)) && stop(id)) return true;
    return false;
  }
  CellKey key;
  for (key[0] = first[0]; key[0] <= last[0]; ++key[0])
    for (key[1] = first[1]; key[1] <= last[1]; ++key[1]) {
      key[2] = first[2];
      const size_t row = index_of(key);
      for (std::int64_t k = 0; k <= last[2] - first[2]; ++k) {
        const size_t cell = row + static_cast<size_t>(k);
        if (fine_of_[cell] < 0) {
          for (int id = head_[cell]; id >= 0; id = next_[static_cast<size_t>(id)])
            if (inside(position(id)) && stop(id)) return true;
          continue;
        }
        const FineCells& sub = fine_[static_cast<size_t>(fine_of_[cell])];
        const CellKey here{key[0], key[1], first[2] + k};
        const auto from = fine_key(here, lo), to = fine_key(here, hi);
        for (std::int64_t a = from[0]; a <= to[0]; ++a)
          for (std::int64_t b = from[1]; b <= to[1]; ++b)
            for (std::int64_t c = from[2]; c <= to[2]; ++c)
              for (int id = sub.head[static_cast<size_t>((a * kFine + b) * kFine + c)]; id >= 0;
                   id = next_[static_cast<size_t>(id)])
                if (inside(position(id)) && stop(id)) return true;
      }
    }
  return false;
}

void PointGrid::in_box(const Vec3& lo, const Vec3& hi, std::vector<int>& out) const {
  out.clear();
  find_in_box(lo, hi, [&out](int id) {
    out.push_back(id);
    return false;
  });
}

void PointGrid::in_ball(const Vec3& centre, double radius, std::vector<int>& out) const {
  const Vec3 r{radius, radius, radius};
  in_box(centre - r, centre + r, out);
  const double r2 = radius * radius;
  out.erase(std::remove_if(out.begin(), out.end(),
                           [&](int id) {
                             const Vec3 d = position(id) - centre;
                             return dot(d, d) > r2;
                           }),
            out.end());
}

bool PointGrid::any_in_ball(const Vec3& centre, double radius) const {
  const Vec3 r{radius, radius, radius};
  const double r2 = radius * radius;
  return find_in_box(centre - r, centre + r, [&](int id) {
    const Vec3 d = position(id) - centre;
    return dot(d, d) <= r2;
  });
}

bool equatorial_sphere_occupants(const PointGrid& grid, int a, int b, int c, std::vector<int>& out) {
  out.clear();
  const Vec3 &pa = grid.position(a), &pb = grid.position(b), &pc = grid.position(c);
  const Ball ball = equatorial_sphere(pa, pb, pc);
  if (!std::isfinite(ball.radius)) return false;
  std::vector<int> near;
  grid.in_ball(ball.centre, safe_radius(ball), near);
  for (int id : near) {
    if (id == a || id == b || id == c) continue;
    if (occupies(side_of_equatorial_sphere(pa, pb, pc, grid.position(id)))) out.push_back(id);
  }
  return true;
}

bool circumsphere_is_empty(const PointGrid& grid, int a, int b, int c, int d) {
  const Vec3 &pa = grid.position(a), &pb = grid.position(b), &pc = grid.position(c),
             &pd = grid.position(d);
  const Ball ball = circumsphere(pa, pb, pc, pd);
  if (!std::isfinite(ball.radius)) return false;
  std::vector<int> near;
  grid.in_ball(ball.centre, safe_radius(ball), near);
  for (int id : near) {
    if (id == a || id == b || id == c || id == d) continue;
    if (occupies(side_of_circumsphere(pa, pb, pc, pd, grid.position(id)))) return false;
  }
  return true;
}

}  // namespace vd
