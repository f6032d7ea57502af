// TRIANGULATE (paper §1): the whole pipeline from a closed tagged surface to
// tetrahedra per region. Each step lives in its own folder (README,
// "Architecture"); this file only runs them in order and times them.
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "delaunay/facet_oracle.h"
#include "mesh/cancel.h"
#include "mesh/mesh.h"
#include "mesh/second_order.h"
#include "quality/tet_quality.h"
#include "surface/delaunayzation.h"
#include "surface/random_shift.h"
#include "volume/advancing_front.h"
#include "volume/interior_vertices.h"
#include "volume/region_tetrahedra.h"
#include "volume/size_field.h"
#include "volume/sliver_removal.h"

namespace vd {

// How the tetrahedra of the final vertex set are made (paper §6): taken from
// the Delaunay tetrahedralization (the default), or by the paper's
// advancing-front Delaunay from the facets alone (--volume advancing-front).
enum class VolumeMethod { delaunay, advancing_front };

struct MeshOptions {
  std::string oracle = "dt";
  OracleOptions oracle_options;
  DelaunayzationOptions delaunayzation;
  double shift = 1e-4;               // random shift, relative to the local size (0: none)
  std::uint64_t seed = 1;
  // Threads for the loops that split evenly (quality figures); 0: one per
  // core. The mesh is the same for any number.
  int threads = 0;
  double sharp_angle_deg = 40.0;     // face patches for input without face ids
  // The input's face ids are face patches the caller assigned (`vdmesh
  // compare`, so that TetGen gets the same markers): smooth faces, as those
  // the mesher assigns itself, not the input's own (InputSurfaceGeometry).
  bool faces_are_patches = false;
  bool validate = true;
  // The surface is a CAD tessellation: a recovery that stops is for the
  // tessellation chain to try again (RecoveryError), even beside edges on one
  // facet only; on a faceted surface with such a gap it is bad input.
  bool tessellated = false;
  bool interior = true;              // interior vertices (paper §2); --no-interior turns them off
  SizeFieldOptions size;             // --size H, gradation
  // --surface-grading R: with interior vertices and flips, surface edges
  // longer than R times the graded surface size are split (0: off; R >= 1).
  double surface_grading = 2.0;
  InteriorOptions interior_options;
  VolumeMethod volume = VolumeMethod::delaunay;  // --volume
  bool remove_slivers = true;
  // --cautious: interior vertices that take no surface facet, and no cap
  // fold splits, from the start: what a run falls back to by itself when
  // the recovery with interior vertices stops (mesh_surface).
  bool cautious = false;
  SliverOptions slivers;             // --sliver-angle
  int order = 1;                     // 2: 10-node tetrahedra, surface nodes on delaunayzation.geometry
  // Called at the start of each phase; empty: silent.
  std::function<void(const std::string& phase)> progress;
  // Set from another thread to stop the run: mesh_surface then throws
  // CancelledError (checked between phases and inside the long loops).
  const std::atomic<bool>* cancel = nullptr;
};

// A quantity the input defines exactly (CAD volume of a solid, area of a
// face) beside the same quantity measured on the mesh.
struct ReferenceMeasure {
  std::string name;  // "Solid2", "Face7"
  double reference = 0;
  double mesh = 0;
};

// The common piece of solids that overlap (an assembly's interference):
// meshed as the first of them.
struct SolidOverlap {
  std::vector<int> solids;  // solid numbers, ascending
  double volume = 0;        // OpenCASCADE's volume of the common piece
};

// Filled for CAD input (core/cad): what was read and how the surface was made.
struct CadInputReport {
  bool used = false;
  std::string units;
  int solids = 0, faces = 0, interface_faces = 0;
  // How the solids were made conformal: "none" (one solid), "glued" (as
  // touching only), "in full" (after a glued surface crossed itself).
  std::string fuse = "none";
  double size = 0;                 // edge length of the tessellation and the interior
  bool size_chosen = false;        // from the part's dimensions (no --size)
  int thin_faces = 0;              // faces of thin solids meshed finer than `size` (chosen size only)
  double thin_size = 0;            // the smallest size of those faces
  double thinnest = 0;             // the smallest mean thickness 2V/A of a solid
  double deflection = 0;           // chord height of the face tessellation (its last round)
  double angle_deg = 0;            // angular deflection of the face tessellation (its last round)
  int tessellation_rounds = 1;     // tessellations made to meet the volume tolerance
  std::vector<int> held_solids;    // solid numbers those rounds left alone: recovery ran away beside them
  int recovery_retries = 0;        // tessellations after recovery stopped at its guards (CadMeshOptions)
  int recovery_runaways = 0;       // of those, recoveries stopped as running away
  double tessellation_volume_error = 0;  // largest |tessellated / CAD volume - 1| of a solid
  int occ_triangles = 0, refine_splits = 0, refine_flips = 0, border_splits = 0, collapsed_edges = 0, surface_facets = 0;
  int flat_vertices_removed = 0;
  int border_caps_snapped = 0;    // inner vertices a hair from a border moved onto it
  int needle_edges_collapsed = 0; // edges under 0.2 of their facets' longest, on faces with a pole not remeshed
  int smoothing_moves = 0;
  int remeshed_faces = 0;         // faces meshed anew inside their border
  bool smoothing_dropped = false;  // the improved tessellation failed; meshed without smoothing
  bool remeshing_dropped = false;  // and without the remeshing
  bool planar_splits_fallback = false;  // every recovery on the CAD geometry stopped: split vertices on chords
  std::vector<ReferenceMeasure> volumes, areas;
  std::vector<SolidOverlap> overlaps;
};

struct MeshReport {
  int input_vertices = 0, input_facets = 0;
  int unused_input_vertices = 0;  // dropped before meshing: no input facet uses them
  int welded_input_vertices = 0;  // repeats of another input vertex's coordinates, made one with it
  int output_vertices = 0, output_facets = 0;
  int added_surface_vertices = 0, added_surface_facets = 0;
  int hole_facets_dropped = 0;       // facets left between two exteriors by region points' holes
  int face_patches_assigned = 0;     // > 0 when face ids came from sharp edges
  int size_splits = 0;               // surface edges split down to the given or graded size
  int size_flips = 0;                // flips inside faces between those splits
  std::vector<long> tets_per_region; // index = region id (0 unused)
  std::string oracle;
  std::string allocator;             // set by the vdmesh command (app/tuned_allocator.h); empty elsewhere
  OracleStats oracle_stats;
  DelaunayzationResult delaunayzation;
  ShiftStats shift;
  RegionStats regions;
  bool advancing_front = false;      // the tetrahedra came from the advancing front
  AdvancingFrontStats front;
  long interior_vertices = 0;
  InteriorStats interior;
  double smallest_size = 0;          // of the size field
  SliverStats slivers;
  QualitySummary quality;
  SecondOrderStats second_order;     // filled when order == 2
  std::vector<std::pair<std::string, double>> seconds;  // per phase, in order
  // The process's peak resident memory (MiB) at the end of each phase, in
  // order; empty where the system does not tell (Linux's /proc does).
  std::vector<std::pair<std::string, double>> peak_mib;
  CadInputReport cad;
  bool complete = false;
  std::vector<std::array<int, 3>> missing_facets;       // vertex ids, when not complete
};

struct MeshResult {
  Mesh mesh;        // output surface (with tags) and tetrahedra (regions > 0)
  MeshReport report;
};

// Throws UsageError for options out of their range (check_mesh_options),
// InputError for invalid input (before any work), CancelledError when
// options.cancel is set during the run (also when it was raised during a
// phase that does not look at it), and RecoveryError
// when Delaunayzation stops at a guard: then `partial` (if given) receives
// the result so far, with the facets still missing in report.missing_facets.
MeshResult mesh_surface(const Mesh& input, const MeshOptions& options, MeshResult* partial = nullptr);

// UsageError naming the first option out of its range (the command line
// and the Python module check theirs first, naming their own options).
void check_mesh_options(const MeshOptions& options);

std::string report_json(const MeshReport& report);
std::string report_table(const MeshReport& report);

}  // namespace vd
