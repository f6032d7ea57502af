// Delaunayhood of a facet (paper §4): is triangle (a, b, c) a face of the
// Delaunay tetrahedralization of the current vertex set? One interface, three
// oracles created by name:
//   "dt"     the exact incremental tetrahedralization (reference, default)
//   "lp"     the paper's IS_DELAUNAY?: stored apex, equatorial sphere,
//            candidate apexes, then Rajan's linear program (GLPK)
//   "sphere" the empty equatorial sphere only (Miller et al., Shewchuk)
// "sphere" is sufficient, not necessary: it may call a Delaunay facet
// non-Delaunay, never the reverse.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "mesh/mesh.h"

namespace vd {

class DelaunayTetrahedralization;

struct OracleOptions {
  // Largest LP (number of unknowns) actually solved; over it the facet counts
  // as non-Delaunay. <0: no limit; 0: never solve an LP.
  int lp_limit = -1;
};

// How the queries were decided. Counts of facet queries, not of facets.
struct OracleStats {
  long queries = 0;
  long delaunay = 0;                   // answers "Delaunay"
  long by_tetrahedralization = 0;      // dt
  long by_stored_apex = 0;             // lp: stored apex sphere still empty
  long by_equatorial_sphere = 0;       // lp, sphere: equatorial sphere empty
  long by_candidate_apex = 0;          // lp: a vertex in the equatorial sphere closes an empty sphere
  long by_lp = 0;                      // lp: decided by solving the LP
  long lp_solved = 0;                  // number of LPs solved
  long lp_unknowns = 0;                // sum of LP sizes (average = lp_unknowns / lp_solved)
  long lp_refused_by_limit = 0;        // over the size limit: counted non-Delaunay
  long lp_ambiguous = 0;               // optimum failed the exact empty-sphere check
};

class FacetOracle {
 public:
  virtual ~FacetOracle() = default;
  virtual std::string name() const = 0;
  // Called once before any query. `points` grows during Delaunayzation (the
  // oracle keeps the pointer); `dt` is the exact tetrahedralization of the
  // same points, kept current by the caller.
  virtual void attach(const std::vector<Vec3>* points, const DelaunayTetrahedralization* dt) = 0;
  // points->at(id) was appended (ids grow by one) or moved.
  virtual void vertex_added(int id) = 0;
  // Is (a, b, c) a face of the Delaunay tetrahedralization of *points?
  // `normal` (any length) says which side to sample first where that matters.
  virtual bool is_delaunay(int a, int b, int c, Vec3 normal) = 0;
  // is_delaunay for every facet of a surface at once, or an empty vector
  // when the oracle has no faster way than one query per facet.
  virtual std::vector<char> are_delaunay(const std::vector<Triangle>&) { return {}; }

  const OracleStats& stats() const { return stats_; }

 protected:
  OracleStats stats_;
};

// Names accepted by make_oracle.
std::vector<std::string> oracle_names();
// Throws vd::UsageError for an unknown name.
std::unique_ptr<FacetOracle> make_oracle(const std::string& name, const OracleOptions& options = {});

}  // namespace vd
