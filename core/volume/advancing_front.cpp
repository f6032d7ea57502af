#include "volume/advancing_front.h"

#include <algorithm>
#include <cmath>
#include <deque>
#include <stdexcept>
#include <string>
#include <unordered_map>

#include "geometry/point_grid.h"
#include "geometry/predicates.h"
#include "mesh/cancel.h"
#include "mesh/tet_faces.h"

namespace vd {
namespace {

// An oriented face: its vertices turned so that the smallest comes first,
// which keeps the orientation; the inner side is where orientation(a, b, c, p)
// is positive.
using Face = std::array<int, 3>;

Face oriented(int a, int b, int c) {
  if (b < a && b < c) return {b, c, a};
  if (c < a && c < b) return {c, a, b};
  return {a, b, c};
}

Face reversed(const Face& f) { return {f[0], f[2], f[1]}; }

std::string face_text(const Face& f) {
  return "(" + std::to_string(f[0]) + ", " + std::to_string(f[1]) + ", " + std::to_string(f[2]) + ")";
}

class Front {
 public:
  Front(const Mesh& m, AdvancingFrontStats& stats, const std::atomic<bool>* cancel)
      : m_(m), stats_(stats), facets_(m.triangles, [](const Triangle& t) { return t.v; }), poll_(cancel, 1024) {
    grid_.build(m.points);
    const Box box = bounding_box(m.points);
    diagonal_ = norm(box.hi - box.lo);
    for (const Triangle& t : m.triangles) {
      if (t.front > 0) push(oriented(t.v[0], t.v[1], t.v[2]), t.front);
      if (t.back > 0) push(oriented(t.v[0], t.v[2], t.v[1]), t.back);
    }
  }

  std::vector<Tetrahedron> run() {
    std::vector<Tetrahedron> tets;
    while (!queue_.empty()) {
      const Face f = queue_.front();
      queue_.pop_front();
      const auto it = open_.find(f);
      if (it == open_.end()) continue;  // closed from its other side meanwhile
      poll_();
      const int region = it->second;
      open_.erase(it);
      ++stats_.front_faces;
      const int d = apex(f);
      const int a = f[0], b = f[1], c = f[2];
      tets.push_back({{a, b, c, d}, region});
      // The other three faces, turned outwards (tet (a, b, c, d) is positive).
      for (const Face& g : {oriented(b, c, d), oriented(a, d, c), oriented(a, b, d)}) close_or_open(g, region);
    }
    if (!open_.empty())
      throw std::runtime_error("advancing front: " + std::to_string(open_.size()) + " faces left open");
    return tets;
  }

 private:
  void push(const Face& f, int region) {
    if (!open_.emplace(f, region).second)
      throw std::runtime_error("advancing front: face " + face_text(f) + " twice on the initial front");
    queue_.push_back(f);
  }

  // g, a face of a new tetrahedron turned away from it: a front face looking
  // into the tetrahedron is closed by it; otherwise g joins the front.
  void close_or_open(const Face& g, int region) {
    const auto inward = open_.find(reversed(g));
    if (inward != open_.end()) {
      if (inward->second != region)
        throw std::runtime_error("advancing front: face " + face_text(g) + " between regions " +
                                 std::to_string(region) + " and " + std::to_string(inward->second) +
                                 " is no facet");
      open_.erase(inward);
      return;
    }
    // A facet whose side here is not on the front: that side is closed
    // already, or it is the exterior.
    if (facets_.find(g) >= 0 || open_.count(g))
      throw std::runtime_error("advancing front: two tetrahedra on one side of face " + face_text(g) +
                               " (a facet that is not Delaunay, or vertices not in general position)");
    push(g, region);
  }

  // The vertex on the inner side of f whose sphere through f holds no other
  // vertex of that side. The spheres through f form a pencil, centres c0 + t n
  // along the normal; on the inner side their balls grow with t, so the
  // apex is the inner vertex of least t, and the ball of any t that holds an
  // inner vertex holds the apex. Balls of t = 0, R, 2R, ... are searched;
  // the exact in-sphere test picks the apex among what they hold, and the
  // apex's circumsphere is searched once more for a vertex rounding left out.
  int apex(const Face& f) {
    const Vec3 &pa = m_.points[f[0]], &pb = m_.points[f[1]], &pc = m_.points[f[2]];
    const Ball equator = equatorial_sphere(pa, pb, pc);
    Vec3 n = cross(pb - pa, pc - pa);
    const double length = norm(n);
    if (!std::isfinite(equator.radius) || !(length > 0))
      throw std::runtime_error("advancing front: face " + face_text(f) + " is flat");
    n = (1.0 / length) * n;
    const double r = equator.radius;
    int best = -1;
    for (double t = 0; best < 0; t = t == 0 ? r : 2 * t) {
      if (t > 1e6 * (diagonal_ + r))
        throw std::runtime_error("advancing front: no vertex on the inner side of face " + face_text(f));
      const Ball ball{equator.centre + t * n, std::sqrt(r * r + t * t)};
      best = best_in(f, ball, -1);
    }
    // The circumsphere once more: a vertex inside it on the inner side is a
    // better apex (then searched again from there).
    for (int round = 0; round < 64; ++round) {
      const int better = best_in(f, circumsphere(pa, pb, pc, m_.points[best]), best);
      if (better == best) return best;
      best = better;
    }
    throw std::runtime_error("advancing front: the apex of face " + face_text(f) + " does not settle");
  }

  // The best apex among `start` (-1: none) and the inner vertices in `ball`.
  int best_in(const Face& f, const Ball& ball, int start) {
    ++stats_.searches;
    const Vec3 &pa = m_.points[f[0]], &pb = m_.points[f[1]], &pc = m_.points[f[2]];
    grid_.in_ball(ball.centre, safe_radius(ball), near_);
    // Ids in increasing order, so that a tie (not general position) goes
    // the same way on every run.
    std::sort(near_.begin(), near_.end());
    int best = start;
    for (int p : near_) {
      if (p == f[0] || p == f[1] || p == f[2] || p == best) continue;
      ++stats_.candidates;
      if (orientation(pa, pb, pc, m_.points[p]) <= 0) continue;
      if (best < 0) {
        best = p;
        continue;
      }
      // Cospherical vertices (a box's corners, which the random shift cannot
      // move) are ordered as CGAL orders them, so the tetrahedra stay CGAL's.
      bool tie = false;
      if (perturbed_side_of_circumsphere(pa, pb, pc, m_.points[best], m_.points[p], &tie) == SphereSide::inside)
        best = p;
      stats_.ties += tie;
    }
    return best;
  }

  const Mesh& m_;
  AdvancingFrontStats& stats_;
  TripleIndex facets_;
  PointGrid grid_;
  double diagonal_ = 0;
  std::unordered_map<Face, int, TripleHash> open_;  // front face -> region on its inner side
  std::deque<Face> queue_;
  std::vector<int> near_;
  CancelPoll poll_;
};

}  // namespace

std::vector<Tetrahedron> advancing_front_tetrahedra(const Mesh& m, AdvancingFrontStats& stats,
                                                   const std::atomic<bool>* cancel) {
  Front front(m, stats, cancel);
  return front.run();
}

}  // namespace vd
