// Keeps each region's volume near its true one while recovery puts split
// vertices on the true surface (CAD input). A split vertex on the true
// surface moves the surface off the chord, outward on a convex face; on a
// thin shell whose outer face recovery splits and whose inner face it
// leaves alone, those moves add up: gmsh_simple_plane.brep's wing shells,
// -0.04 to -0.17 % off their CAD volume in the tessellation (the inner and
// outer chords' errors cancel), ended 0.54 to 0.73 % over it. A split
// vertex that would take a region farther past the limit stays on the
// chord, as in the paper.
#pragma once

#include <vector>

#include "mesh/mesh.h"

namespace vd {

class VolumeKeeper {
 public:
  VolumeKeeper() = default;
  // `target`: each region's true volume by region id (0: not kept).
  // `limit`: the relative error past which a move may not go farther.
  VolumeKeeper(const Mesh& m, std::vector<double> target, double limit);

  bool active() const { return limit_ > 0 && !target_.empty(); }
  // The vertex splitting edge (p, q) of the facets `sharing` put at `point`
  // instead of on the chord: true, and the volumes updated, unless that
  // takes a region farther past the limit.
  bool take_split(const Mesh& m, int p, int q, const std::vector<int>& sharing, const Vec3& point);
  // The flip of facets `t`, `t2` into `a`, `b` (all of one face and sides)
  // moves the surface too.
  void record_flip(const Mesh& m, const Triangle& t, const Triangle& t2, const Triangle& a, const Triangle& b);
  // Relative error of region r now (0 when not kept).
  double error(int region) const;

 private:
  bool kept(int region) const {
    return region > 0 && region < static_cast<int>(target_.size()) && target_[region] > 0;
  }
  // Volume change of the regions on the two sides of a facet of `sides`.
  void add(const Triangle& sides, double change, std::vector<std::pair<int, double>>& out) const;

  std::vector<double> target_, volume_;
  double limit_ = 0;
};

}  // namespace vd
