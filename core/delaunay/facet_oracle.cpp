#include "delaunay/facet_oracle.h"

#include "delaunay/oracles.h"
#include "mesh/error.h"

namespace vd {

std::vector<std::string> oracle_names() { return {"dt", "lp", "sphere"}; }

std::unique_ptr<FacetOracle> make_oracle(const std::string& name, const OracleOptions& options) {
  if (name == "dt") return make_dt_oracle();
  if (name == "lp") return make_lp_oracle(options);
  if (name == "sphere") return make_sphere_oracle();
  throw UsageError("unknown oracle '" + name + "' (choose dt, lp or sphere)");
}

}  // namespace vd
