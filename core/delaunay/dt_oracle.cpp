// The reference oracle: a facet is Delaunay when it is a face of the exact
// tetrahedralization the caller keeps current.
#include <algorithm>

#include "delaunay/delaunay_tetrahedralization.h"
#include "delaunay/oracles.h"

namespace vd {
namespace {

class DtOracle final : public FacetOracle {
 public:
  std::string name() const override { return "dt"; }
  void attach(const std::vector<Vec3>*, const DelaunayTetrahedralization* dt) override { dt_ = dt; }
  void vertex_added(int) override {}
  bool is_delaunay(int a, int b, int c, Vec3) override {
    ++stats_.queries;
    ++stats_.by_tetrahedralization;
    const bool yes = dt_->has_facet(a, b, c);
    stats_.delaunay += yes;
    return yes;
  }
  std::vector<char> are_delaunay(const std::vector<Triangle>& facets) override {
    std::vector<char> yes = dt_->has_facets(facets);
    stats_.queries += static_cast<long>(facets.size());
    stats_.by_tetrahedralization += static_cast<long>(facets.size());
    stats_.delaunay += std::count(yes.begin(), yes.end(), 1);
    return yes;
  }

 private:
  const DelaunayTetrahedralization* dt_ = nullptr;
};

}  // namespace

std::unique_ptr<FacetOracle> make_dt_oracle() { return std::make_unique<DtOracle>(); }

}  // namespace vd
