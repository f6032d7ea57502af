#include "volume/sliver_improvement.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <exception>
#include <limits>
#include <memory>
#include <optional>
#include <thread>
#include <unordered_map>
#include <utility>
#include <vector>

#include "geometry/predicates.h"
#include "mesh/parallel.h"
#include "mesh/progress.h"
#include "mesh/tet_faces.h"
#include "quality/tet_quality.h"
#include "surface/surface_geometry.h"
#include "volume/facet_witnesses.h"

namespace vd {

namespace {

using Triple = std::array<int, 3>;

// Smaller gains are not worth a change (and a strict gain rules out cycles).
constexpr double kMinGainDeg = 1e-6;
// -kNotHeld lies below every score (they lie in [-2, 1]): a tetrahedron
// not held, and a position a held one refuses.
constexpr double kNotHeld = 10.0;
// Largest number of tetrahedra around an edge that edge removal considers.
constexpr int kMaxRing = 7;
// The facet look-ups that moves of vertices on curved faces may make in a
// pass, per surface facet (move_a_vertex).
constexpr long kCurvedTestsPerFacet = 100;

// True when (a, b, c, d) lists the vertices of v as an even permutation of v,
// i.e. with the orientation of v.
bool same_orientation(const std::array<int, 4>& v, int a, int b, int c, int d) {
  const int want[4] = {a, b, c, d};
  int pos[4];
  for (int i = 0; i < 4; ++i) pos[i] = static_cast<int>(std::find(v.begin(), v.end(), want[i]) - v.begin());
  int inversions = 0;
  for (int i = 0; i < 4; ++i)
    for (int j = i + 1; j < 4; ++j) inversions += pos[i] > pos[j];
  return inversions % 2 == 0;
}

// The vertex of v that is not in f.
int apex(const std::array<int, 4>& v, const Triple& f) {
  for (int x : v)
    if (x != f[0] && x != f[1] && x != f[2]) return x;
  return -1;
}

// The tetrahedra of the mesh with their face adjacency and vertex stars,
// changed in place by flips; surface facets are the faces that no change may
// remove.
class TetComplex {
 public:
  // `measures`: the tetrahedra's qualities (measure()) when the caller has
  // them, one per tetrahedron; else empty.
  TetComplex(Mesh& m, std::vector<double> measures)
      : m_(m),
        own_star_(m.points.size(), -1),
        stamp_(m.points.size(), 0),
        on_surface_(m.points.size(), false),
        facets_at_(m.points.size()) {
    for (const Triangle& t : m.triangles) {
      const Triple k = sorted_triple(t.v);
      facets_at_[k[0]].push_back({k[1], k[2]});
      for (int v : t.v) on_surface_[v] = true;
    }
    // Room for the tetrahedra flips add (a few per cent at most) without
    // doubling every array. The tetrahedra and their qualities are taken
    // over, not copied: a copy beside its original was 3.5 MB more at the
    // sliver pass's peak on the 125k box.
    const size_t n = m.tets.size(), room = sliver_pass_room(n);
    tets_ = std::move(m.tets);
    m.tets = std::vector<Tetrahedron>();
    tets_.reserve(room);
    alive_.reserve(room);
    alive_.assign(n, true);
    failed_at_.reserve(room);
    failed_at_.assign(n, -1);
    nbr_.reserve(room);
    nbr_.assign(n, {kUnknown, kUnknown, kUnknown, kUnknown});
    fixed_.reserve(room);
    fixed_.assign(n, 0);
    const bool measured = measures.size() == n;
    quality_ = measured ? std::move(measures) : std::vector<double>(n, 0.0);
    quality_.reserve(room);
    if (!measured) {
      // Measured apart, on every core: a third of building the complex.
      for_each_chunk(static_cast<long>(n), 1 << 14, [&](long, long begin, long end) {
        for (long t = begin; t < end; ++t) quality_[t] = measure(tets_[t].v);
      });
    }
    // The stars in one array, counted then filled, in tetrahedron order.
    star_start_.assign(m.points.size() + 1, 0);
    for (const Tetrahedron& t : tets_)
      for (int v : t.v) ++star_start_[v + 1];
    for (size_t v = 0; v < m.points.size(); ++v) star_start_[v + 1] += star_start_[v];
    star_flat_.resize(star_start_.back());
    std::vector<int> fill(star_start_.begin(), star_start_.end() - 1);
    for (int t = 0; t < size(); ++t)
      for (int v : tets_[t].v) star_flat_[fill[v]++] = t;
  }

  const Vec3& point(int v) const { return m_.points[v]; }
  // A new vertex inside the region, in no tetrahedron yet (add() puts it in).
  int add_point(const Vec3& p) {
    const int v = static_cast<int>(m_.points.size());
    m_.points.push_back(p);
    if (!m_.point_size.empty()) m_.point_size.push_back(0.0);  // as the other interior vertices
    own_star_.push_back(static_cast<int>(owned_stars_.size()));
    owned_stars_.emplace_back();
    stamp_.push_back(0);
    on_surface_.push_back(false);
    facets_at_.emplace_back();
    return v;
  }
  void move_point(int v, const Vec3& p) {
    m_.points[v] = p;
    for (int t : star(v)) {
      quality_[t] = measure(tets_[t].v);
      for (int x : tets_[t].v) touch(x);
    }
  }

  // Whether anything that a flip or move for t looks at (the tetrahedra
  // around its vertices and their shapes) changed since t last failed.
  bool worth_retrying(int t) const {
    long latest = 0;
    for (int x : tets_[t].v) latest = std::max(latest, stamp_[x]);
    return latest > failed_at_[t];
  }
  void mark_failed(int t) { failed_at_[t] = clock_; }
  int size() const { return static_cast<int>(tets_.size()); }
  bool alive(int t) const { return alive_[t]; }
  const Tetrahedron& tet(int t) const { return tets_[t]; }
  double quality(int t) const { return quality_[t]; }
  bool on_surface(int v) const { return on_surface_[v]; }
  // The live tetrahedra around v, in the order they were made.
  struct Star {
    const int *first, *last;
    const int* begin() const { return first; }
    const int* end() const { return last; }
  };
  size_t star_size(int v) const {
    const Star s = star(v);
    return static_cast<size_t>(s.end() - s.begin());
  }
  Star star(int v) const {
    if (own_star_[v] >= 0) {
      const std::vector<int>& s = owned_stars_[own_star_[v]];
      return {s.data(), s.data() + s.size()};
    }
    return {star_flat_.data() + star_start_[v], star_flat_.data() + star_start_[v + 1]};
  }

  double measure(const std::array<int, 4>& v) const {
    return smallest_dihedral_if_positive(point(v[0]), point(v[1]), point(v[2]), point(v[3]));
  }
  // The same order as measure() without the acos (see smallest_dihedral_score).
  double score(const std::array<int, 4>& v) const {
    return smallest_dihedral_score(point(v[0]), point(v[1]), point(v[2]), point(v[3]));
  }
  bool exactly_positive(const std::array<int, 4>& v) const {
    return orientation(point(v[0]), point(v[1]), point(v[2]), point(v[3])) > 0;
  }

  // The tetrahedron across face f of t, or -1 when f is a surface facet.
  int across(int t, const Triple& f) const {
    const int i = face_index(tets_[t].v, f);
    if (i < 0) return -1;
    if (nbr_[t][i] == kUnknown) resolve(t, i);
    return fixed_[t] >> i & 1 ? -1 : nbr_[t][i];
  }

  int add(const Tetrahedron& t) {
    const int id = append(t, measure(t.v));
    for (int v : t.v) {
      own_star(v).push_back(id);
      touch(v);
    }
    return id;
  }

  void kill(int id) {
    alive_[id] = false;
    const Tetrahedron& t = tets_[id];
    for (int i = 0; i < 4; ++i) {
      auto& s = own_star(t.v[i]);
      s.erase(std::find(s.begin(), s.end(), id));
      const int u = nbr_[id][i];
      if (u < 0) continue;
      for (int k = 0; k < 4; ++k)
        if (nbr_[u][k] == id) nbr_[u][k] = kUnknown;
      nbr_[id][i] = kUnknown;
    }
  }

  // The tetrahedra around edge (a, b) and their other vertices in ring order,
  // (a, b, ring[i], ring[i+1]) positive, starting from the first made. False
  // when a face around the edge is a surface facet (the edge is on the
  // surface or crosses it) or the ring has more than max_ring (at most
  // kMaxRing) tetrahedra.
  //
  // The tetrahedra are those in both stars (sorted: one merge), chained by
  // their vertices. Walking from one to the next across the faces linked
  // each face on the way from the stars of its three vertices: on a box of
  // 125k tetrahedra 30k such links were 2 % of a run's instructions.
  bool edge_ring(int a, int b, int max_ring, std::vector<int>& tets, std::vector<int>& ring) const {
    tets.clear();
    ring.clear();
    std::array<int, kMaxRing> around;
    std::array<std::array<int, 2>, kMaxRing> sides;  // each one's (c, d), (a, b, c, d) positive
    int n = 0;
    const Star sa = star(a), sb = star(b);
    for (const int *x = sa.begin(), *y = sb.begin(); x != sa.end() && y != sb.end();) {
      if (*x < *y) {
        ++x;
      } else if (*y < *x) {
        ++y;
      } else {
        if (n == max_ring || n == kMaxRing) return false;
        around[n++] = *x;
        ++x, ++y;
      }
    }
    if (n == 0) return false;
    for (int i = 0; i < n; ++i) {
      const std::array<int, 4>& v = tets_[around[i]].v;
      int c = -1, d = -1;
      for (int x : v)
        if (x != a && x != b) (c < 0 ? c : d) = x;
      if (!same_orientation(v, a, b, c, d)) std::swap(c, d);
      sides[i] = {c, d};
    }
    const int t0 = around[0], region = tets_[t0].region;
    ring = {sides[0][0], sides[0][1]};
    tets = {t0};
    for (int k = 0;;) {
      const int last = ring.back();
      // Across face (a, b, last): the one other tetrahedron on it, unless
      // the face is a surface facet, on the hull (none) or in three (broken).
      if (is_facet({a, b, last})) return false;
      int next = -1, on_face = 0;
      for (int i = 0; i < n; ++i)
        if (i != k && (sides[i][0] == last || sides[i][1] == last)) next = i, ++on_face;
      if (on_face != 1 || tets_[around[next]].region != region) return false;
      if (next == 0) {
        const bool closed = last == ring.front();
        ring.pop_back();
        return closed && ring.size() == tets.size();
      }
      if (static_cast<int>(tets.size()) >= max_ring) return false;
      tets.push_back(around[next]);
      ring.push_back(sides[next][0] == last ? sides[next][1] : sides[next][0]);
      k = next;
    }
  }

  // Alive tetrahedra in their order (originals first, then those made by
  // flips), back into the mesh.
  void write_back() {
    size_t kept = 0;
    for (int t = 0; t < size(); ++t)
      if (alive_[t]) tets_[kept++] = tets_[t];
    tets_.resize(kept);
    m_.tets = std::move(tets_);
  }

 private:
  void touch(int v) { stamp_[v] = ++clock_; }

  Mesh& m_;
  std::vector<Tetrahedron> tets_;
  std::vector<bool> alive_;
  std::vector<double> quality_;
  std::vector<long> failed_at_;  // clock_ when the tetrahedron last failed to improve
  // Stars: those of the first tetrahedra in one flat array (one allocation
  // instead of one per vertex), and a vertex's own vector from the first
  // change around it on.
  std::vector<int> star_start_, star_flat_;
  std::vector<int> own_star_;  // index into owned_stars_, -1: still in star_flat_
  std::vector<std::vector<int>> owned_stars_;
  std::vector<long> stamp_;      // clock_ of the last change around each vertex
  long clock_ = 0;
  std::vector<bool> on_surface_;
  // Face adjacency per tetrahedron (the tetrahedron across face i, -1 for
  // none, kUnknown until asked) and which faces no change may remove (bit
  // i): walks around edges read arrays. A hash map of faces was a third of a
  // sliver pass, half of it two look-ups per step around an edge. Filled on
  // demand: linking every face up front was 15 % of a whole run on a box
  // (865k tetrahedra), and the pass asks about the few around slivers.
  static constexpr int kUnknown = -2;
  mutable std::vector<std::array<int, 4>> nbr_;
  mutable std::vector<unsigned char> fixed_;
  // The surface facets by their smallest vertex: (middle, largest).
  std::vector<std::vector<std::pair<int, int>>> facets_at_;

  // A tetrahedron without its stars (they are filled by the caller).
  int append(const Tetrahedron& t, double quality) {
    const int id = size();
    tets_.push_back(t);
    alive_.push_back(true);
    failed_at_.push_back(-1);
    quality_.push_back(quality);
    nbr_.push_back({kUnknown, kUnknown, kUnknown, kUnknown});
    fixed_.push_back(0);
    return id;
  }
  std::vector<int>& own_star(int v) {
    if (own_star_[v] < 0) {
      own_star_[v] = static_cast<int>(owned_stars_.size());
      owned_stars_.emplace_back(star_flat_.begin() + star_start_[v], star_flat_.begin() + star_start_[v + 1]);
    }
    return owned_stars_[own_star_[v]];
  }

  bool is_facet(const Triple& f) const {
    const Triple k = sorted_triple(f);
    for (const auto& [b, c] : facets_at_[k[0]])
      if (b == k[1] && c == k[2]) return true;
    return false;
  }
  // The tetrahedra on face f: those in the stars of all three of its
  // vertices. Stars are sorted (filled in tetrahedron order, new ones
  // appended with larger ids, removals keep the order), so the three lists
  // are merged: reading a star's ids is one or two cache lines, where
  // checking each tetrahedron of a star for the face read it from anywhere
  // in the array (a resolve was 19 such reads, 0.84 us, on the 125k box).
  template <class Visit>
  void tets_on(const Triple& f, const Visit& visit) const {
    const Star a = star(f[0]), b = star(f[1]), c = star(f[2]);
    const int *x = a.begin(), *y = b.begin(), *z = c.begin();
    while (x != a.end() && y != b.end() && z != c.end()) {
      const int top = std::max({*x, *y, *z});
      if (*x < top) ++x;
      else if (*y < top) ++y;
      else if (*z < top) ++z;
      else visit(top), ++x, ++y, ++z;
    }
  }
  // Links face i of t to the tetrahedron on its other side. A face of three
  // tetrahedra (broken input) is left alone: fixed in all of them.
  void resolve(int t, int i) const {
    const Triple f = face_opposite(tets_[t].v, i);
    int other = -1, j_other = -1, count = 0;
    tets_on(f, [&](int u) {
      if (u == t) return;
      ++count;
      other = u, j_other = face_index(tets_[u].v, f);
    });
    if (count <= 1) {
      nbr_[t][i] = other;
      if (other >= 0) nbr_[other][j_other] = t;
      if (is_facet(f)) {
        fixed_[t] |= 1 << i;
        if (other >= 0) fixed_[other] |= 1 << j_other;
      }
      return;
    }
    nbr_[t][i] = -1;
    fixed_[t] |= 1 << i;
    tets_on(f, [&](int u) {
      if (u == t) return;
      const int j = face_index(tets_[u].v, f);
      nbr_[u][j] = -1;
      fixed_[u] |= 1 << j;
    });
  }
  // The index of the vertex of v opposite face f, -1 when f is not a face of v.
  static int face_index(const std::array<int, 4>& v, const Triple& f) {
    int missing = -1, found = 0;
    for (int i = 0; i < 4; ++i) {
      if (v[i] == f[0] || v[i] == f[1] || v[i] == f[2]) ++found;
      else missing = i;
    }
    return found == 3 ? missing : -1;
  }
};

// A set of tetrahedra that may replace others with the same boundary.
struct Replacement {
  enum Kind { flip_23, flip_32, edge_removal } kind = flip_23;
  std::vector<int> old_tets;
  std::vector<Tetrahedron> new_tets;
  double old_quality = 0, new_quality = -1;
};

template <class Tets>
double min_quality(const TetComplex& c, const Tets& tets) {
  double q = 180;
  for (int t : tets) q = std::min(q, c.quality(t));
  return q;
}

// 2-3 flip across face i of t: the face goes, the edge between the two apexes comes.
bool face_swap(const TetComplex& c, int t, int i, Replacement& r) {
  const Tetrahedron& tt = c.tet(t);
  const int a = tt.v[i];
  Triple f = face_opposite(tt.v, i);
  if (!same_orientation(tt.v, f[0], f[1], f[2], a)) std::swap(f[1], f[2]);
  const int u = c.across(t, f);
  if (u < 0) return false;
  const int b = apex(c.tet(u).v, f);
  r.kind = Replacement::flip_23;
  r.old_tets = {t, u};
  r.old_quality = std::min(c.quality(t), c.quality(u));
  r.new_tets.clear();
  r.new_quality = 180;
  // With a above f (orientation (f, a) positive) and b below, (p, q, b, a)
  // is positive for each edge (p, q) of f when segment ab crosses f.
  for (int e = 0; e < 3; ++e) {
    const Tetrahedron n{{f[e], f[(e + 1) % 3], b, a}, tt.region};
    r.new_quality = std::min(r.new_quality, c.measure(n.v));
    r.new_tets.push_back(n);
  }
  return r.new_quality > 0;
}

// Edge removal: the tetrahedra around edge (a, b) replaced by the pairs
// (triangle, a) and (triangle, b) over the triangulation of the ring polygon
// with the largest smallest angle (dynamic programming over sub-polygons).
bool remove_edge(const TetComplex& c, int a, int b, Replacement& r) {
  std::vector<int> tets, ring;
  if (!c.edge_ring(a, b, kMaxRing, tets, ring)) return false;
  const int n = static_cast<int>(ring.size());
  const int region = c.tet(tets[0]).region;
  // For ring positions i < k < j: (ri, rk, rj, b) and (ri, rj, rk, a) are the
  // positive orders, given (a, b, r_i, r_i+1) positive.
  auto pair_of = [&](int i, int k, int j) {
    return std::array<std::array<int, 4>, 2>{std::array<int, 4>{ring[i], ring[k], ring[j], b},
                                             std::array<int, 4>{ring[i], ring[j], ring[k], a}};
  };
  // Scores, not degrees (the same order, no acos): this search was a third
  // of a sliver pass.
  auto triangle_score = [&](int i, int k, int j) {
    const auto p = pair_of(i, k, j);
    return std::min(c.score(p[0]), c.score(p[1]));
  };
  // A sub-polygon's triangle is worth measuring only when its two sides
  // could still lift the best so far, and above the old tetrahedra's
  // quality: no triangulation at or under that is ever taken, so values
  // there may stay low without changing what is taken.
  const double old_quality = min_quality(c, tets);
  const double floor_score = dihedral_score_of_degrees(old_quality);
  constexpr double kOpen = std::numeric_limits<double>::infinity();
  std::vector<double> best(n * n, kOpen);
  std::vector<int> split(n * n, -1);
  for (int len = 2; len < n; ++len)
    for (int i = 0; i + len < n; ++i) {
      const int j = i + len;
      double q = -2;  // the score of a tetrahedron that is not positive
      for (int k = i + 1; k < j; ++k) {
        const double sides = std::min(best[i * n + k], best[k * n + j]);
        if (sides <= q || sides <= floor_score) continue;
        const double v = std::min(sides, triangle_score(i, k, j));
        if (v > q) q = v, split[i * n + j] = k;
      }
      best[i * n + j] = q;
    }
  r.kind = n == 3 ? Replacement::flip_32 : Replacement::edge_removal;
  r.old_tets = tets;
  r.old_quality = old_quality;
  r.new_quality = dihedral_degrees_of_score(best[n - 1]);
  r.new_tets.clear();
  if (!(r.new_quality > 0)) return false;
  std::vector<std::pair<int, int>> todo{{0, n - 1}};
  while (!todo.empty()) {
    const auto [i, j] = todo.back();
    todo.pop_back();
    if (j - i < 2) continue;
    const int k = split[i * n + j];
    for (const auto& v : pair_of(i, k, j)) r.new_tets.push_back({v, region});
    todo.push_back({i, k});
    todo.push_back({k, j});
  }
  return true;
}

// The best flip that removes tetrahedron t (case B), if one improves.
bool best_flip(const TetComplex& c, int t, Replacement& best) {
  Replacement r;
  bool found = false;
  auto consider = [&] {
    if (r.new_quality > r.old_quality + kMinGainDeg && (!found || r.new_quality > best.new_quality)) {
      best = r;
      found = true;
    }
  };
  for (int i = 0; i < 4; ++i)
    if (face_swap(c, t, i, r)) consider();
  const std::array<int, 4> v = c.tet(t).v;
  for (int i = 0; i < 4; ++i)
    for (int j = i + 1; j < 4; ++j)
      if (remove_edge(c, v[i], v[j], r)) consider();
  return found;
}

bool apply_if_valid(TetComplex& c, const Replacement& r, SliverStats& stats) {
  for (const Tetrahedron& t : r.new_tets)
    if (!c.exactly_positive(t.v)) return false;
  for (int t : r.old_tets) c.kill(t);
  for (const Tetrahedron& t : r.new_tets) c.add(t);
  (r.kind == Replacement::flip_23 ? stats.flips_23 : r.kind == Replacement::flip_32 ? stats.flips_32
                                                                                     : stats.edge_removals)++;
  return true;
}

// Where a surface vertex may slide: in a plane when every facet around it has
// the same face id and regions and the same normal (to 1e-6 degrees) and they
// close a disc around it; along a line when the facets lie in two such planes
// that meet along a straight crease through it. Sliding there leaves the
// surface's shape and the regions' volumes as they are (to rounding). On
// CAD input, a vertex inside a curved face (every facet around it of that
// face and regions, closing a disc) slides on the face: the search goes in
// its tangent plane, and the position taken is projected onto the face
// (`surface`). It changes the chords' shape, not the face they follow: a
// tube 1 thick kept a tetrahedron of 6.8 deg across its wall, whose four
// vertices, two on each cylinder, had nowhere to go.
struct SlidePlane {
  Vec3 origin, normal, u, w;
  bool line = false;  // along u only
  int axis = -1;      // plane: x, y or z = origin's; line: along that axis. Kept exactly.
  const SurfaceGeometry* surface = nullptr;  // on a curved face: onto it
  int face = 0;
  // Where a vertex going to p in the plane (or line) comes to rest: on the
  // curved face, when no farther from p than p from `from`.
  std::optional<Vec3> settle(const Vec3& from, const Vec3& p) const {
    if (!surface) return onto(p);
    const std::optional<Vec3> q = surface->project_onto_face(face, p, from);
    if (!q || !(norm(*q - p) <= norm(p - from))) return std::nullopt;
    return q;
  }
  // The plane through `at` with unit normal n, and a basis of it.
  static SlidePlane through(const Vec3& at, const Vec3& n) {
    SlidePlane plane;
    plane.origin = at;
    plane.normal = n;
    const Vec3 helper = std::abs(n.x) < 0.9 ? Vec3{1, 0, 0} : Vec3{0, 1, 0};
    plane.u = normalized(cross(n, helper));
    plane.w = cross(n, plane.u);
    return plane;
  }
  Vec3 onto(Vec3 p) const {
    if (line) {
      if (axis < 0) return origin + dot(p - origin, u) * u;
      Vec3 q = origin;
      q[axis] = p[axis];
      return q;
    }
    if (axis == 0) p.x = origin.x;
    else if (axis == 1) p.y = origin.y;
    else if (axis == 2) p.z = origin.z;
    else p = p - dot(p - origin, normal) * normal;
    return p;
  }
};

// By surface vertex, for those that may slide: a map, since a vector over
// all vertices was a tenth of the sliver pass's peak memory.
using SlidePlanes = std::unordered_map<int, SlidePlane>;

// Two facets of one face that meet at more than this slide no vertex on the
// face, when the face ids are the input's own (the face patches of untagged
// input split at such edges, assign_face_patches' default). TetGen's example
// PLC, whose face markers go round its box's corners, lost a corner to a
// slide (region 10: 11.9375 -> 11.9863) after the cap points' clearance
// changed its mesh on 2026-12-02. On patches too, the armadillo fell from
// 15.86 to 10.23 deg and the rocker arm from 18.65 to 16.90: a patch joins
// facets round a sharp edge through their other neighbours, and slides there
// were kept.
constexpr double kSharpEdgeInFaceDeg = 40.0;

// How many corners two facets share.
int shared_corners(const Triangle& a, const Triangle& b) {
  int n = 0;
  for (int x : a.v) n += x == b.v[0] || x == b.v[1] || x == b.v[2];
  return n;
}

SlidePlanes slide_planes(const Mesh& m, const SurfaceGeometry* geometry) {
  const double cos_smooth_in_face = std::cos(kSharpEdgeInFaceDeg * M_PI / 180.0);
  std::vector<std::vector<int>> around(m.points.size());
  for (size_t f = 0; f < m.triangles.size(); ++f)
    for (int v : m.triangles[f].v) around[v].push_back(static_cast<int>(f));
  SlidePlanes planes;
  auto area_vector = [&](const Triangle& t) {
    return cross(m.points[t.v[1]] - m.points[t.v[0]], m.points[t.v[2]] - m.points[t.v[0]]);
  };
  // The axis a vector lies along exactly (its other two components are 0), or -1.
  auto exact_axis = [](const Vec3& d) {
    for (int k = 0; k < 3; ++k)
      if (d[(k + 1) % 3] == 0 && d[(k + 2) % 3] == 0 && d[k] != 0) return k;
    return -1;
  };
  // Facets of one plane: normals within 1e-13 rad (by the sine, which keeps
  // its digits where the cosine is 1). A vertex sliding by d leaves a facet's
  // plane by d times that angle; at 1e-6 deg (1.7e-8 rad), as before, moves
  // on the anchor at a 20 deg sliver angle took facets 1e-9 of an edge off
  // their planes.
  const double max_sine = 1e-13;
  std::vector<std::pair<int, int>> link;
  for (size_t v = 0; v < around.size(); ++v) {
    const std::vector<int>& fs = around[v];
    if (fs.size() < 3) continue;
    // Link vertex -> facets around v using it, in a list: a hash map per
    // vertex was half of this function (1.1 % of a run on a box).
    link.clear();
    for (int f : fs)
      for (int x : m.triangles[f].v) {
        if (x == static_cast<int>(v)) continue;
        auto it = std::find_if(link.begin(), link.end(), [x](const std::pair<int, int>& e) { return e.first == x; });
        if (it == link.end()) link.emplace_back(x, 1);
        else ++it->second;
      }
    bool disc = true;
    for (const auto& [x, uses] : link) disc = disc && uses == 2;
    if (!disc) continue;
    // On a curved face (below), when no plane takes it.
    auto on_curved_face = [&] {
      if (!geometry) return;
      const Triangle& first = m.triangles[fs[0]];
      Vec3 sum{0, 0, 0};
      for (int f : fs) {
        const Triangle& t = m.triangles[f];
        if (t.face != first.face || t.front != first.front || t.back != first.back) return;
        sum = sum + area_vector(t);
      }
      // Not at a sharp edge inside the face: a face id of tagged input may
      // hold a box's corner, which sliding on the facets cuts off. (A CAD
      // face is smooth, its facets' edges sharp only where its tessellation
      // is coarse: the U-joint's has some, and slides there mend 10 of its
      // tetrahedra under 10 deg.)
      if (geometry->faces_may_be_sharp()) {
        std::vector<Vec3> normal(fs.size());
        for (size_t i = 0; i < fs.size(); ++i) normal[i] = normalized(area_vector(m.triangles[fs[i]]));
        for (size_t i = 0; i < fs.size(); ++i)
          for (size_t j = i + 1; j < fs.size(); ++j)
            if (shared_corners(m.triangles[fs[i]], m.triangles[fs[j]]) == 2 &&
                dot(normal[i], normal[j]) < cos_smooth_in_face)
              return;
      }
      if (!(norm(sum) > 0)) return;
      SlidePlane plane = SlidePlane::through(m.points[v], normalized(sum));
      plane.surface = geometry;
      plane.face = first.face;
      planes.emplace(v, plane);
    };
    // The facets by plane: at most two planes, each of one face id and regions.
    std::vector<int> group(fs.size(), -1);
    int leader[2] = {-1, -1};
    bool ok = true;
    for (size_t i = 0; i < fs.size() && ok; ++i) {
      const Triangle& t = m.triangles[fs[i]];
      const Vec3 n = normalized(area_vector(t));
      for (int g = 0; g < 2 && group[i] < 0; ++g) {
        if (leader[g] < 0) {
          leader[g] = static_cast<int>(i);
          group[i] = g;
        } else {
          const Triangle& l = m.triangles[fs[leader[g]]];
          if (t.face == l.face && t.front == l.front && t.back == l.back &&
              dot(n, normalized(area_vector(l))) > 0 && norm(cross(n, normalized(area_vector(l)))) <= max_sine)
            group[i] = g;
        }
      }
      ok = group[i] >= 0;
    }
    if (!ok) {
      on_curved_face();
      continue;
    }
    SlidePlane plane;
    plane.origin = m.points[v];
    if (leader[1] < 0) {
      Vec3 sum{0, 0, 0};
      for (int f : fs) sum = sum + area_vector(m.triangles[f]);
      if (!(norm(sum) > 0)) continue;
      plane = SlidePlane::through(m.points[v], normalized(sum));
      plane.axis = exact_axis(area_vector(m.triangles[fs[0]]));
    } else {
      // The crease: the two link vertices whose edges to v have a facet of each plane.
      std::unordered_map<int, int> seen;  // link vertex -> groups it touches (bits)
      for (size_t i = 0; i < fs.size(); ++i)
        for (int x : m.triangles[fs[i]].v)
          if (x != static_cast<int>(v)) seen[x] |= 1 << group[i];
      std::vector<int> ends;
      for (const auto& [x, bits] : seen)
        if (bits == 3) ends.push_back(x);
      if (ends.size() != 2) {
        on_curved_face();
        continue;
      }
      std::sort(ends.begin(), ends.end());
      const Vec3 chord = m.points[ends[1]] - m.points[ends[0]];
      const Vec3 d = normalized(chord);
      const Vec3 n0 = normalized(area_vector(m.triangles[fs[leader[0]]]));
      const Vec3 n1 = normalized(area_vector(m.triangles[fs[leader[1]]]));
      const Vec3 off = m.points[v] - m.points[ends[0]];
      if (!(norm(cross(off, d)) <= 1e-12 * norm(chord)) || !(std::abs(dot(d, n0)) <= 1e-12) ||
          !(std::abs(dot(d, n1)) <= 1e-12)) {
        on_curved_face();
        continue;
      }
      plane.line = true;
      plane.u = d;
      plane.w = Vec3{0, 0, 0};
      plane.normal = n0;
      plane.axis = exact_axis(chord);
      const int k = plane.axis;
      if (k >= 0 && (off[(k + 1) % 3] != 0 || off[(k + 2) % 3] != 0)) continue;  // not exactly on it
    }
    planes.emplace(v, plane);
  }
  return planes;
}

// The 26 directions of a compass search (cube neighbours, unit length).
std::vector<Vec3> compass_directions() {
  std::vector<Vec3> d;
  for (int x = -1; x <= 1; ++x)
    for (int y = -1; y <= 1; ++y)
      for (int z = -1; z <= 1; ++z)
        if (x || y || z) d.push_back(normalized(Vec3{double(x), double(y), double(z)}));
  return d;
}

// Compass search from x, whose score is q: steps of 0.2 `spacing` along
// each direction (each position through `place`), the best taken while it
// gains, the step halved when none does, down to 1e-3 `spacing`. `score(y,
// floor)` may stop at anything at or under floor once y cannot beat it.
template <class Place, class Score>
void compass_search(const std::vector<Vec3>& directions, double spacing, const Place& place, const Score& score,
                    Vec3& x, double& q) {
  double step = 0.2 * spacing;
  for (int round = 0; round < 40 && step > 1e-3 * spacing; ++round) {
    Vec3 best = x;
    double best_q = q;
    for (const Vec3& d : directions) {
      const Vec3 y = place(x + step * d);
      const double qy = score(y, best_q);
      if (qy > best_q) best = y, best_q = qy;
    }
    if (best_q > q + 1e-12) x = best, q = best_q;
    else step *= 0.5;
  }
}

// Where vertex v should go: the position with the largest smallest dihedral
// angle over the tetrahedra around it, by compass search from the better of
// its position and the centroid of its neighbours; in `plane` when given (a
// surface vertex). With `hold_worse`, the tetrahedra around v already worse
// than `old_quality` (the sliver being mended) are held instead: they may
// not get worse, and the smallest angle is taken over the others. Returns
// the smallest angle there (old_quality when nothing better was found).
double best_position(const TetComplex& c, int v, double old_quality, const SlidePlane* plane, bool hold_worse,
                     Vec3& to) {
  struct Local {
    std::array<Vec3, 4> p;
    int slot;
    double held = -kNotHeld;  // the score a worse tetrahedron may not go under
  };
  std::vector<Local> local;
  Vec3 centroid{0, 0, 0};
  double spacing = 0;
  int neighbours = 0;
  for (int t : c.star(v)) {
    Local l;
    for (int i = 0; i < 4; ++i) {
      const int x = c.tet(t).v[i];
      l.p[i] = c.point(x);
      if (x == v) l.slot = i;
      else centroid = centroid + l.p[i], spacing += norm(l.p[i] - c.point(v)), ++neighbours;
    }
    local.push_back(l);
  }
  if (!neighbours) return old_quality;
  // Worst first: a candidate position is mostly refused by the tetrahedra
  // that are bad now, and quality_at stops at the first one under the best
  // so far (the search itself does not depend on this order).
  const double level = dihedral_score_of_degrees(old_quality);
  {
    std::vector<std::pair<double, size_t>> order;
    for (size_t i = 0; i < local.size(); ++i)
      order.emplace_back(smallest_dihedral_score(local[i].p[0], local[i].p[1], local[i].p[2], local[i].p[3]), i);
    std::sort(order.begin(), order.end());
    std::vector<Local> sorted;
    sorted.reserve(local.size());
    for (const auto& [score, i] : order) {
      sorted.push_back(local[i]);
      if (hold_worse && score < level) sorted.back().held = score;
    }
    local = std::move(sorted);
  }
  centroid = (1.0 / neighbours) * centroid;
  spacing /= neighbours;
  // Score of the smallest angle with v at x (smallest_dihedral_score),
  // stopping early once it cannot beat `floor`.
  auto quality_at = [&](const Vec3& x, double floor) {
    double lo = 1.0;
    for (const Local& l : local) {
      const Vec3* p[4] = {&l.p[0], &l.p[1], &l.p[2], &l.p[3]};
      p[l.slot] = &x;
      if (l.held > -kNotHeld) {
        // Under its held score? The floor just below it stops at the first
        // angle that is, and gives the whole score otherwise.
        const double below = std::nextafter(l.held, -kNotHeld);
        if (smallest_dihedral_score_above(*p[0], *p[1], *p[2], *p[3], below) < l.held) return -kNotHeld;
        continue;
      }
      lo = std::min(lo, smallest_dihedral_score_above(*p[0], *p[1], *p[2], *p[3], floor));
      if (lo <= floor) return lo;
    }
    return lo;
  };
  static const std::vector<Vec3> all_directions = compass_directions();
  std::vector<Vec3> in_plane;
  if (plane && plane->line) in_plane = {plane->u, -1.0 * plane->u};
  else if (plane)
    for (int k = 0; k < 8; ++k) {
      const double angle = k * M_PI / 4;
      in_plane.push_back(std::cos(angle) * plane->u + std::sin(angle) * plane->w);
    }
  const std::vector<Vec3>& directions = plane ? in_plane : all_directions;
  auto place = [&](const Vec3& y) { return plane ? plane->onto(y) : y; };
  Vec3 x = c.point(v);
  double q = level;
  centroid = place(centroid);
  const double qc = quality_at(centroid, q);
  if (qc > q) x = centroid, q = qc;
  compass_search(directions, spacing, place, quality_at, x, q);
  to = x;
  return dihedral_degrees_of_score(q);
}

// Is a tetrahedron around v worse than `quality` (a move of v with
// hold_worse would hold it)?
bool worse_around(const TetComplex& c, int v, double quality) {
  for (int s : c.star(v))
    if (c.quality(s) < quality) return true;
  return false;
}

// Case C for tetrahedron t: the best accepted move of one of its vertices
// (interior ones anywhere, surface ones in their slide plane). With
// `hold_worse`, the tetrahedra around a vertex that are worse than t are
// held (see best_position): the move mends t without making anything
// under it worse.
// `unchanged`: nothing around t changed since its moves last failed, so
// only a vertex with a worse tetrahedron around it (one held now) is tried.
bool move_a_vertex(TetComplex& c, FacetWitnesses* w, const SlidePlanes& planes, int t, bool hold_worse,
                   bool unchanged, long& curved_tests_left, SliverStats& stats) {
  int best_v = -1;
  Vec3 best_to;
  double best_gain = kMinGainDeg;
  bool blocked = false;
  // Vertices on curved faces only when no other vertex of t may move: such
  // a move reshapes the surface's chords and costs a projection, and tried
  // with the others it took the CAD corpus's 21 meshes from 76 to 204 s.
  // Their look-ups of facets are held to kCurvedTestsPerFacet a facet: on
  // gmsh_simple_plane.brep, whose wing skins are far thinner than their
  // facets, each of their allows() looked at 22,500 facets (57 on a
  // spherical shell 0.5 thick, 194 on the ellipses), and even tried last,
  // 32,374 such moves took its pass from 3.3 to 76 s (7,068 -> 2,025
  // tetrahedra under 10 deg).
  for (int round = 0; round < (curved_tests_left > 0 ? 2 : 1) && best_v < 0; ++round) {
    for (int v : c.tet(t).v) {
      const SlidePlane* plane = nullptr;
      if (c.on_surface(v)) {
        const auto it = planes.find(v);
        if (it != planes.end()) plane = &it->second;
      }
      if (c.on_surface(v) && !plane) continue;
      if ((plane && plane->surface) != (round == 1)) continue;
      if (unchanged && !worse_around(c, v, c.quality(t))) continue;
      const double old_q = hold_worse ? c.quality(t) : min_quality(c, c.star(v));
      Vec3 to;
      const double new_q = best_position(c, v, old_q, plane, hold_worse, to);
      if (new_q - old_q <= best_gain) continue;
      // Shorter moves along the same way when the full one would make a
      // surface facet non-Delaunay.
      const Vec3 from = c.point(v);
      for (int halving = 0; halving < 5; ++halving) {
        Vec3 p = from + std::ldexp(1.0, -halving) * (to - from);
        if (plane) {
          const std::optional<Vec3> rest = plane->settle(from, p);
          if (!rest) continue;
          p = *rest;
        }
        bool positive = true;
        double q = 180;
        for (int s : c.star(v)) {
          std::array<Vec3, 4> x;
          for (int i = 0; i < 4; ++i) x[i] = c.tet(s).v[i] == v ? p : c.point(c.tet(s).v[i]);
          positive = positive && orientation(x[0], x[1], x[2], x[3]) > 0;
          const double qs = smallest_dihedral_if_positive(x[0], x[1], x[2], x[3]);
          if (hold_worse && c.quality(s) < old_q) positive = positive && qs >= c.quality(s);  // held
          else q = std::min(q, qs);
          if (!positive || q - old_q <= best_gain) break;  // refused whatever the rest give
        }
        if (!positive || q - old_q <= best_gain) continue;
        if (w) {
          const long tests_before = w->tests_made();
          const bool allowed = w->allows(p, v);
          if (round == 1) curved_tests_left -= w->tests_made() - tests_before;
          if (!allowed || (plane && !w->reshape_allows(v, p))) {
            blocked = true;
            continue;
          }
        }
        best_v = v, best_to = p, best_gain = q - old_q;
        break;
      }
    }
  }
  if (best_v < 0) {
    stats.moves_blocked += blocked;
    return false;
  }
  c.move_point(best_v, best_to);
  if (w) w->moved(best_v, best_to);
  ++stats.moves;
  stats.held_moves += hold_worse;
  stats.surface_moves += c.on_surface(best_v);
  return true;
}

// Case D for tetrahedron t, once flips and moves (holding worse ones) left
// it under kInsertBelowDeg: a new vertex, placed where the cavity it opens
// gets the largest smallest dihedral angle. The cavity grows from t over
// the tetrahedra whose circumsphere holds the point (never across a surface
// facet), then over those behind any of its boundary faces the point does
// not see; the new tetrahedra are the boundary faces coned to the point, a
// valid filling once every one is positive by the exact predicate (the
// cavity is star-shaped from the point). The point starts at t's
// circumcentre, else its centroid, and goes where a compass search over
// the fixed boundary takes it. Taken when the new tetrahedra's smallest
// angle beats the cavity's and fewer of them are under kInsertBelowDeg:
// without that count, on gmsh_lever.stl and c3tm_nefertiti.obj it made
// more tetrahedra under 10 deg than it mended.
constexpr int kMaxCavity = 48;
constexpr double kInsertBelowDeg = 10.0;

// The cavity for a point p near t, and its boundary faces as (tetrahedron,
// slot of the vertex that p replaces); false when none fits in kMaxCavity
// tetrahedra, or one would leave a vertex inside it.
bool cavity_of(const TetComplex& c, int t, const Vec3& p, std::vector<int>& cavity,
               std::vector<std::pair<int, int>>& boundary) {
  cavity = {t};
  auto in_cavity = [&](int u) { return std::find(cavity.begin(), cavity.end(), u) != cavity.end(); };
  for (size_t k = 0; k < cavity.size(); ++k) {
    const std::array<int, 4> v = c.tet(cavity[k]).v;
    for (int i = 0; i < 4; ++i) {
      const int u = c.across(cavity[k], face_opposite(v, i));
      if (u < 0 || in_cavity(u)) continue;
      const std::array<int, 4>& w = c.tet(u).v;
      if (side_of_circumsphere(c.point(w[0]), c.point(w[1]), c.point(w[2]), c.point(w[3]), p) != SphereSide::inside)
        continue;
      if (static_cast<int>(cavity.size()) == kMaxCavity) return false;
      cavity.push_back(u);
    }
  }
  for (bool grew = true; grew;) {
    grew = false;
    boundary.clear();
    for (size_t k = 0; k < cavity.size(); ++k) {
      const std::array<int, 4> v = c.tet(cavity[k]).v;
      for (int i = 0; i < 4; ++i) {
        const int u = c.across(cavity[k], face_opposite(v, i));
        if (u >= 0 && in_cavity(u)) continue;
        std::array<Vec3, 4> x;
        for (int j = 0; j < 4; ++j) x[j] = j == i ? p : c.point(v[j]);
        if (orientation(x[0], x[1], x[2], x[3]) > 0) {
          boundary.push_back({cavity[k], i});
          continue;
        }
        if (u < 0 || static_cast<int>(cavity.size()) == kMaxCavity) return false;
        cavity.push_back(u);
        grew = true;
      }
    }
  }
  for (int u : cavity)
    for (int x : c.tet(u).v) {
      bool on_boundary = false;
      for (const auto& [owner, i] : boundary)
        for (int j = 0; j < 4; ++j) on_boundary = on_boundary || (j != i && c.tet(owner).v[j] == x);
      if (!on_boundary) return false;
    }
  return true;
}

bool insert_a_vertex(TetComplex& c, int t, SliverStats& stats) {
  const std::array<int, 4> v = c.tet(t).v;
  const Vec3 &a = c.point(v[0]), &b = c.point(v[1]), &cc = c.point(v[2]), &d = c.point(v[3]);
  const Ball ball = circumsphere(a, b, cc, d);
  std::vector<Vec3> starts{0.25 * (a + b + cc + d)};
  if (std::isfinite(ball.radius)) starts.insert(starts.begin(), ball.centre);
  const double low_score = dihedral_score_of_degrees(kInsertBelowDeg);
  std::vector<int> cavity;
  std::vector<std::pair<int, int>> boundary;
  for (const Vec3& start : starts) {
    if (!cavity_of(c, t, start, cavity, boundary)) continue;
    // Each new tetrahedron as its points, the new vertex's slot last to fill.
    struct Cone {
      std::array<Vec3, 4> p;
      int slot;
    };
    std::vector<Cone> cones;
    double spacing = 0;
    for (const auto& [owner, i] : boundary) {
      Cone k{{}, i};
      for (int j = 0; j < 4; ++j) k.p[j] = c.point(c.tet(owner).v[j]);
      spacing += norm(k.p[(i + 1) % 4] - start);
      cones.push_back(k);
    }
    spacing /= static_cast<double>(cones.size());
    // The score of the smallest angle with the new vertex at x, or anything
    // at or under `floor` once it cannot beat it.
    auto score_at = [&](const Vec3& x, double floor) {
      double lo = 1.0;
      for (Cone& k : cones) {
        k.p[k.slot] = x;
        lo = std::min(lo, smallest_dihedral_score_above(k.p[0], k.p[1], k.p[2], k.p[3], floor));
        if (lo <= floor) return lo;
      }
      return lo;
    };
    const double old_score = dihedral_score_of_degrees(min_quality(c, cavity));
    static const std::vector<Vec3> directions = compass_directions();
    Vec3 x = start;
    double q = score_at(x, -kNotHeld);
    compass_search(directions, spacing, [](const Vec3& y) { return y; }, score_at, x, q);
    if (!(dihedral_degrees_of_score(q) > dihedral_degrees_of_score(old_score) + kMinGainDeg)) continue;
    long old_low = 0, new_low = 0;
    for (int u : cavity) old_low += c.quality(u) < kInsertBelowDeg;
    bool positive = true;
    for (Cone& k : cones) {
      k.p[k.slot] = x;
      new_low += smallest_dihedral_score(k.p[0], k.p[1], k.p[2], k.p[3]) < low_score;
      positive = positive && orientation(k.p[0], k.p[1], k.p[2], k.p[3]) > 0;
    }
    if (new_low >= old_low || !positive) continue;
    std::vector<Tetrahedron> made;
    for (const auto& [owner, i] : boundary) made.push_back(c.tet(owner));
    const int p = c.add_point(x);
    for (size_t k = 0; k < made.size(); ++k) made[k].v[boundary[k].second] = p;
    for (int u : cavity) c.kill(u);
    for (const Tetrahedron& n : made) c.add(n);
    ++stats.insertions;
    return true;
  }
  return false;
}

}  // namespace

void improve_slivers(Mesh& m, const SliverOptions& o, const FacetApexes& apexes, SliverStats& stats,
                     const std::function<void()>& apexes_done, std::vector<double> measures) {
  std::unique_ptr<FacetWitnesses> witnesses;
  stats.delaunay_surface = o.delaunay_surface;
  SlidePlanes planes;
  if (o.moves) planes = slide_planes(m, o.geometry);
  // Case C moves interior vertices, and surface vertices with a slide
  // plane. Without either (a surface-only run on a curved surface) nothing
  // can move, and the witnesses (SliverOptions::delaunay_surface), 1.4 s of
  // the elephant's 6.7 s pass with --no-interior, would never be asked.
  const std::vector<char> on_surface = surface_vertex_flags(m.points.size(), m.triangles);
  const bool has_interior_vertex = std::find(on_surface.begin(), on_surface.end(), 0) != on_surface.end();
  const bool can_move = o.moves && (!planes.empty() || has_interior_vertex);
  // The apexes are all the witnesses need of the tetrahedralization: it goes
  // before they and the complex are built, and is not in memory beside
  // either (on a box of 125k tetrahedra its 11.5 MB and the witnesses'
  // 2.6 MB side by side were the run's peak).
  std::optional<TetComplex> built;
  if (can_move && o.delaunay_surface) {
    const std::vector<std::array<int, 2>> apexes_of = apexes(m.triangles);
    if (apexes_done) apexes_done();
    // The witnesses (read the points and facets) and the complex (takes
    // the tetrahedra) side by side: each was about 4 % of a run on a box of
    // 125k tetrahedra, and the witnesses' set-up is sequential.
    const auto build_witnesses = [&] { witnesses = std::make_unique<FacetWitnesses>(m.points, m.triangles, apexes_of); };
    if (thread_count() > 1 && o.witnesses_beside) {
      std::exception_ptr failure;
      std::thread beside([&] {
        try {
          build_witnesses();
        } catch (...) {
          failure = std::current_exception();
        }
      });
      try {
        built.emplace(m, std::move(measures));
      } catch (...) {
        beside.join();
        throw;
      }
      beside.join();
      if (failure) std::rethrow_exception(failure);
    } else {
      build_witnesses();
    }
  } else if (apexes_done) {
    apexes_done();
  }
  if (!built) built.emplace(m, std::move(measures));
  TetComplex& c = *built;
  // The tetrahedra under `angle`, worst first.
  auto slivers_under = [&c](double angle) {
    std::vector<std::pair<double, int>> out;
    for (int t = 0; t < c.size(); ++t)
      if (c.alive(t) && c.quality(t) < angle) out.emplace_back(c.quality(t), t);
    std::sort(out.begin(), out.end());
    return out;
  };
  double angle = o.sliver_angle_deg;
  // Changes made at the first angle, and the raised angle's allowance.
  long first_changes = 0, allowance = -1;
  long curved_tests_left = kCurvedTestsPerFacet * static_cast<long>(m.triangles.size());
  for (;;) {
    // hold 0: each move judged by the worst tetrahedron around the vertex.
    // hold 1, on what that left: the tetrahedra worse than the one mended
    // are held instead (best_position). Scored by the worst of them all, a
    // vertex could not move while a worse neighbour stayed put, whoever's
    // vertex it was (gmsh_lever.stl: tetrahedra of four interior vertices
    // left at 6 to 9 deg beside ones of 2 to 5 deg on the surface). Only
    // after the first: from the start it left cgal_anchor_dense.off at
    // 0.37 deg instead of 1.11. After it (2026-11-28): the anchor 1.11 ->
    // 1.40 deg, the lever 1,663 -> 1,636 tetrahedra under 10 deg (its pass
    // 2.9 -> 4.0 s), gmsh_U_Joint_2.stp 242 -> 196, gmsh_ellipses.brep 750
    // -> 664; no smallest angle lower on the surface inputs or CAD corpus.
    for (int hold = 0; hold < (o.hold_worse && can_move ? 2 : 1); ++hold) {
      for (int pass = 0; pass < o.max_passes && allowance != 0; ++pass) {
        const std::vector<std::pair<double, int>> slivers = slivers_under(angle);
        long changes = 0;
        size_t tried = 0;
        for (const auto& [quality, t] : slivers) {
          // Progress: the share of this pass's slivers looked at.
          if ((++tried & 255) == 0) set_phase_fraction(static_cast<double>(tried) / static_cast<double>(slivers.size()));
          if (allowance == 0) break;
          if (!c.alive(t) || c.quality(t) >= angle) continue;
          // What failed and has not changed since fails again, but for a
          // move that holds a worse tetrahedron: only that is new (and
          // move_a_vertex tries only such moves then).
          const bool changed = c.worth_retrying(t);
          if (!changed && !hold) continue;
          Replacement r;
          if ((changed && o.flips && best_flip(c, t, r) && apply_if_valid(c, r, stats)) ||
              (can_move && move_a_vertex(c, witnesses.get(), planes, t, hold == 1, !changed, curved_tests_left, stats)) ||
              (changed && hold == 1 && quality < kInsertBelowDeg && o.inserts && !witnesses && insert_a_vertex(c, t, stats))) {
            ++changes;
            if (allowance < 0) {
              ++first_changes;
            } else {
              ++stats.raised_changes;
              if (--allowance == 0) stats.raised_allowance_used = true;
            }
            continue;
          }
          c.mark_failed(t);
        }
        if (!changes) break;
      }
    }
    if (angle >= o.raised_angle_deg || !slivers_under(angle).empty()) break;
    angle = o.raised_angle_deg;
    stats.raised_to_deg = angle;
    // Every change keeps the tetrahedra it makes above the ones it replaces,
    // so the pass may stop anywhere at the raised angle: past this many
    // changes it does. A plate 50 x 50 x 0.2 (115k tetrahedra) made 2,673
    // at 10 deg in 1.1 s, then 89k at 20 deg in 10 s for 10.0 -> 10.7 deg.
    allowance = std::max(o.raised_changes_per_first * first_changes, std::max(o.raised_changes_at_least, 1L));
  }
  c.write_back();
}

}  // namespace vd
