// The empty equatorial sphere oracle (Miller et al., Shewchuk): a facet whose
// smallest circumscribed sphere holds no other vertex is a face of every
// Delaunay tetrahedralization (the sphere itself witnesses it). Sufficient,
// not necessary: a Delaunay facet with a vertex in its equatorial sphere is
// called non-Delaunay. The test is exact and a vertex on the sphere counts as
// inside, so a "yes" never depends on how a degenerate tie is broken.
#include "delaunay/oracles.h"
#include "geometry/point_grid.h"

namespace vd {
namespace {

class SphereOracle final : public FacetOracle {
 public:
  std::string name() const override { return "sphere"; }

  void attach(const std::vector<Vec3>* points, const DelaunayTetrahedralization*) override {
    points_ = points;
    grid_.build(*points);
  }

  void vertex_added(int id) override { grid_.update(id, points_->at(static_cast<size_t>(id))); }

  bool is_delaunay(int a, int b, int c, Vec3) override {
    ++stats_.queries;
    grid_.catch_up(*points_);
    if (!grid_.has_triangle(a, b, c)) return false;
    std::vector<int> occupants;
    if (!equatorial_sphere_occupants(grid_, a, b, c, occupants) || !occupants.empty()) return false;
    ++stats_.by_equatorial_sphere;
    ++stats_.delaunay;
    return true;
  }

 private:
  const std::vector<Vec3>* points_ = nullptr;
  PointGrid grid_;
};

}  // namespace

std::unique_ptr<FacetOracle> make_sphere_oracle() { return std::make_unique<SphereOracle>(); }

}  // namespace vd
