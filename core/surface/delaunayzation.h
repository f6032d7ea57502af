// Surface Delaunayzation (paper §5): flips within topological faces and
// splits at longest-edge mid-points until every surface facet is a face of
// the Delaunay tetrahedralization of the vertex set.
#pragma once

#include <cstdint>
#include <vector>

#include "delaunay/facet_oracle.h"
#include "mesh/cancel.h"
#include "mesh/mesh.h"

namespace vd {

class EdgeMap;

class DelaunayTetrahedralization;
class SurfaceGeometry;

struct DelaunayzationOptions {
  bool flips = true;
  double flip_angle_deg = 20.0;  // largest angle between the normals of a flipped pair
  // >0: a flip may move the surface by at most this (the distance between
  // the quadrilateral's two diagonals). CAD input sets the chord height.
  double max_flip_offset = 0;
  // By face id, where > 0: the bound of that face's flips instead (CAD
  // input: each face's chord height). The smallest one everywhere stopped
  // the flips at gmsh_simple_plane.brep's wing roots once its nose had
  // chords 20 times finer, and recovery ran away there.
  std::vector<double> face_flip_offset;
  // Guards: the paper gives no termination proof.
  int max_passes = 200;
  int max_added_vertices = -1;   // <0: 20 x input vertices + 1000
  // Also stops after this many passes in a row that add no vertex and leave
  // as many facets missing (only flips back and forth are left).
  int max_stalled_passes = 5;
  // >0: also stops once this many passes have gone by without fewer facets
  // missing than the fewest so far. For callers with another way out (CAD
  // input tessellated again): a recovery that runs away rarely comes back.
  int patience_passes = 0;
  // Also stops a recovery that runs away (as patience_passes > 0 does)
  // without the patience: for a recovery that may need many passes, where
  // one that runs away does not come back (CAD input).
  bool stop_running_away = false;
  // Split an edge from a corner of the input (a vertex of three or more
  // faces) at a power of two from the corner instead of its middle (see
  // split_edge). Off by default: on the CAD corpus it lowered as many
  // smallest angles as it raised (the U-joint 0.34 -> 0.00 deg, caxif 8.79
  // -> 3.38); mesh_cad turns it on for a last try of its chain of
  // tessellations when every one of them stopped.
  bool shell_splits = false;
  double min_edge_relative = 1e-7;  // edges shorter than this x bbox diagonal are not split
  std::uint64_t seed = 1;        // position of each split point near the mid-point
  double split_jitter = 1e-4;    // relative to the edge length, along the edge
  // Places split vertices on the true surface (CAD input); null: on the chord.
  const SurfaceGeometry* geometry = nullptr;
  // >0, with a geometry that knows its regions' volumes: a split vertex
  // stays on the chord where the true surface would take a region's volume
  // farther than this (relative) from the true one (VolumeKeeper).
  double volume_limit = 0;
  // Set from another thread to stop: delaunayize then throws CancelledError.
  const std::atomic<bool>* cancel = nullptr;
  // Set from another thread when the work is moot (the surface was found to
  // cross itself): delaunayize returns at its next pass or split, incomplete.
  const std::atomic<bool>* abandon = nullptr;
};

struct DelaunayzationResult {
  int passes = 0;
  int flips = 0;
  int splits = 0;            // split operations (one new vertex each)
  int splits_on_chord = 0;   // with a SurfaceGeometry: kept on the chord, the true point being too far off
  int splits_on_chord_for_volume = 0;  // of those, kept there for a region's volume (volume_limit)
  int added_vertices = 0;
  int added_facets = 0;      // final facet count - input facet count
  int oracle_wrong = 0;      // oracle said Delaunay, the exact check said not
  std::vector<int> missing;  // facets still not Delaunay when a guard stopped the work
  bool ran_away = false;     // stopped as running away (patience_passes > 0 or stop_running_away only)
  bool shell_splits = false; // DelaunayzationOptions::shell_splits was on
  bool complete() const { return missing.empty(); }
};

// Where a vertex splitting the surface edge (p, q) of the facets `sharing`
// goes on CAD input: `chord` (on the edge) moved onto the true surface, unless
// that is far off the chord for the facets it splits (then `chord`, and
// *kept_on_chord is set).
Vec3 place_split_point(const Mesh& m, const SurfaceGeometry& geometry, int p, int q, const std::vector<int>& sharing,
                       const Vec3& chord, bool* kept_on_chord = nullptr);

// Works on `surface` (points and triangles) in place: flips and splits change
// its triangles, splits append points (with sizes, when point_size is set).
// `dt` holds the tetrahedralization of all surface.points (and any interior
// vertices appended to them); it is updated as vertices are added.
// `edges`, when given, is the edge map of surface.triangles as they are, taken
// over (moved from) instead of built again.
DelaunayzationResult delaunayize(Mesh& surface, DelaunayTetrahedralization& dt, FacetOracle& oracle,
                                 const DelaunayzationOptions& options, EdgeMap* edges = nullptr);

}  // namespace vd
