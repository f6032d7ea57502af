// Constructors of the oracles behind FacetOracle (facet_oracle.h), one per file.
#pragma once

#include <memory>

#include "delaunay/facet_oracle.h"

namespace vd {

std::unique_ptr<FacetOracle> make_dt_oracle();
std::unique_ptr<FacetOracle> make_lp_oracle(const OracleOptions& options);
std::unique_ptr<FacetOracle> make_sphere_oracle();
// The version of the GLPK library the lp oracle runs on (`vdmesh --version`).
const char* lp_solver_version();

}  // namespace vd
