// CAD input (STEP, IGES, BREP) through OpenCASCADE: read, make touching
// solids conformal, tessellate with face and region tags, and answer where
// surface points belong. The OpenCASCADE types stay inside core/cad/*.cpp so
// that the rest of vdmesh builds without their headers.
//
// Tags: region i is Solid<i> and face j is Face<j>, 1-based, numbered the way
// FreeCAD numbers the sub-shapes of the shape it shows (TopExp::MapShapes
// order); after a general fuse each solid and face keeps the number of the
// input sub-shape it came from (README, "CAD input").
#pragma once

#include <atomic>
#include <cctype>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "mesh/mesh.h"
#include "pipeline/mesher.h"
#include "surface/surface_geometry.h"

namespace vd::cad {

// A path's extension in lower case (".step").
inline std::string lower_extension(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return ext;
}

// .step .stp .iges .igs .brep .brp, any case. Inline: the program asks before
// it loads the CAD plugin (cad/cad_plugin.h).
inline bool is_cad_file_name(const std::string& path) {
  const std::string ext = lower_extension(path);
  return ext == ".step" || ext == ".stp" || ext == ".iges" || ext == ".igs" || ext == ".brep" || ext == ".brp";
}

// OpenCASCADE's mesher refuses a chord height under its precision
// (Precision::Confusion(), 1e-7 in the model's units) with "invalid parameter
// value"; the options say so first.
constexpr double kSmallestDeflection = 1e-7;
// A chord height given by hand is at least this fraction of the part's
// bounding-box diagonal (CadModel::tessellate).
constexpr double kSmallestRelativeDeflection = 1e-7;

struct TessellationOptions {
  double size = 0;              // target edge length; 0: chosen from the part (report says which)
  double deflection = 0;        // chord height of OpenCASCADE's mesher; 0: min(size / 10, min over solids 2V/A / 50)
  double angle_deg = 20;        // angular deflection of OpenCASCADE's mesher
  // With the automatic chord height: > 0 starts every face at this chord
  // height instead of its solids' thickness / 50 (the volume rounds go on
  // from there).
  double start_deflection = 0;
  // Face numbers where a recovery ran away on an earlier tessellation: the
  // volume rounds make no solid on either side of them finer.
  std::vector<int> runaway_faces;
  // With the automatic chord height: while a solid's tessellated volume is
  // off its CAD volume by more than this fraction, tessellate again with the
  // chord height and the angle made smaller (at most kMaxTessellationRounds
  // tessellations, kMaxFacetGrowth times the facets; stops when the error
  // does not shrink with the chords). 0: tessellate once.
  double volume_tolerance = 0.004;
  // With the size chosen (size 0), on a part whose solids touch nowhere: a
  // solid whose mean thickness 2V/A is under the size over this gets this
  // times that thickness as the size of its faces, within a facet budget
  // (cad_surface.cpp, thin_solid_face_sizes). 0: off.
  double thin_size_factor = 4.0;
  bool refine = true;           // split edges longer than `size`, new vertices on the CAD geometry
  bool flips = true;            // improve triangle shape by flips inside each face
  // > 0: also split edges longer than this times the mean graded size of
  // their ends (the tessellation's shortest edges, grown by `gradation`
  // along the edges; see refine_surface_to_size), so a narrow face's
  // needles become triangles about as long as the face is wide.
  double grading = 0;
  double gradation = 0.3;
  bool smooth = true;           // move vertices inside faces where a corner is poor (on the CAD face)
  bool remesh = true;           // faces meshed anew inside their border (cad_remesh.cpp)
  const std::atomic<bool>* cancel = nullptr;  // raised: stop with CancelledError (mesh/cancel.h)
};

struct TessellationStats {
  double size = 0;              // the size used (given or chosen)
  bool size_chosen = false;
  int thin_faces = 0;           // faces of thin solids given a size under `size` (thin_size_factor)
  double thin_size = 0;         // the smallest of their sizes
  double thinnest = 0;          // the smallest mean thickness 2V/A of a solid (0: none measured)
  double deflection = 0;        // the smallest chord height used (of the last round)
  double angle_deg = 0;         // the smallest angular deflection used (of the last round)
  std::vector<double> face_deflection;  // by face number (Face<n>): each face's chord height
  int rounds = 1;               // tessellations made (volume_tolerance)
  std::vector<int> held_solids;  // solid numbers the rounds left alone (TessellationOptions::runaway_faces)
  double volume_error = 0;      // the largest relative volume error of a solid's tessellation
  int occ_triangles = 0;        // from OpenCASCADE's mesher, before refinement
  int refine_splits = 0;
  int refine_flips = 0;
  int smoothing_moves = 0;
  int remeshed_faces = 0;
  int border_splits = 0;        // facets with two edges on one CAD edge, split at their centre
  int border_caps_snapped = 0;  // inner vertices a hair from a border moved onto it
  int needle_edges_collapsed = 0;  // on faces with a pole not remeshed, edges under 0.2 of their facets' longest
  int dropped_degenerate = 0;   // collapsed triangles at degenerate edges (cone apexes, poles)
  int dropped_folded = 0;       // pairs of one face's triangles on the same nodes, facing away from each other
  int flat_vertices_removed = 0;  // inner vertices of three facets on their neighbours' edge (cad_collapse.cpp)
  int collapsed_edges = 0;      // edges far below the chord height collapsed (OpenCASCADE's near-duplicate nodes)
  double seconds_tessellate = 0, seconds_refine = 0;
};

constexpr int kMaxTessellationRounds = 4;
constexpr double kMaxFacetGrowth = 6;  // the last round's facets / the first's, at most about
constexpr double kMaxRoundFacets = 1e6;  // no further round expected to give more facets

// Does a volume round push a solid the rounds leave alone (`held`, by solid
// index) over the tolerance, where the round it would replace (`before`)
// had it within, and further than the worst solid the rounds refine still
// is after it? The rounds then judge it worse, whatever it does for the
// solids they refine: no later round looks at that solid again. On
// gmsh_simple_plane.brep at 0.6 times its size a round that took a nose
// piece from 1.27 to 0.43 % took the fuselage shells behind the nose, held,
// from 0.28 to 5.3 % (their faces lost their remeshing; cad_remesh.cpp).
// Over the tolerance but under the worst refined solid is allowed: at its
// default size a round that took the refined solids from 5.33 % to 1.62 %
// took the held Solid7 from under 0.4 to 0.456 %, and judged worse, it left
// 12 solids over 0.5 % instead of 4 (2026-12-01).
inline bool pushes_a_held_solid_over(const std::vector<double>& before, const std::vector<double>& after,
                                     const std::vector<char>& held, double tolerance) {
  double refined_worst = 0;  // after the round, of the solids the rounds refine
  for (size_t i = 0; i < after.size() && i < held.size(); ++i)
    if (!held[i]) refined_worst = std::max(refined_worst, after[i]);
  const double bound = std::max(tolerance, refined_worst);
  for (size_t i = 0; i < after.size() && i < before.size() && i < held.size(); ++i)
    if (held[i] && after[i] > bound && before[i] <= tolerance) return true;
  return false;
}

using GeometryCheck = ReferenceMeasure;  // cad = reference

class CadModel {
 public:
  // Reads a .step/.stp, .iges/.igs or .brep/.brp file (case-insensitive) and
  // fuses touching solids. Throws InputError naming the file and, for open
  // shells or shapes without solids, the shape.
  // A raised `cancel` flag stops the transfer, sewing and fuse within a
  // fraction of a second (CancelledError); parsing the file does not look.
  // `fuse`: how solids are made conformal (Fuse::glued_first only for
  // mesh_cad, which checks the glued surface and fuses again if need be).
  enum class Fuse { in_full, glued_first };
  static CadModel read(const std::string& path, const std::atomic<bool>* cancel = nullptr, Fuse fuse = Fuse::in_full);
  // A BREP in memory (the Python module and FreeCAD hand shapes over this way).
  static CadModel from_brep_string(const std::string& brep, const std::string& name = "<brep>",
                                   const std::atomic<bool>* cancel = nullptr, Fuse fuse = Fuse::in_full);

  CadModel(CadModel&&) noexcept;
  CadModel& operator=(CadModel&&) noexcept;
  ~CadModel();

  int solid_count() const;
  int face_count() const;               // faces of the solids (the ones meshed)
  int interface_face_count() const;     // faces shared by two solids
  double bbox_diagonal() const;
  std::string units() const;            // "mm" for STEP/IGES (converted), "as given" for BREP
  double seconds_read = 0, seconds_fuse = 0;
  // The solids were fused as only touching (OpenCASCADE's gluing): faster,
  // and the same shape wherever solids meet at faces, edges or vertices
  // only. Solids that cross are left unsplit: their tessellation crosses
  // itself, and mesh_cad meshes fused_in_full() instead.
  bool glued() const;
  // "none" (one solid, no fuse), "glued" or "in full": the report's cad.fuse.
  std::string fuse_kind() const;
  // The model of the same solids fused in full (the solids that cross each
  // other split at their intersections). Only for a glued model.
  CadModel fused_in_full(const std::atomic<bool>* cancel = nullptr) const;

  // A size from the part's dimensions when the user gives none.
  double default_size() const;
  // The closed, welded, tagged surface: face ids = CAD face numbers, front/back
  // regions = solid numbers (0 outside), names "Face<j>"/"Solid<i>".
  Mesh tessellate(const TessellationOptions& options, TessellationStats* stats = nullptr) const;
  // Places split vertices on the CAD faces and edges (see SurfaceGeometry).
  std::unique_ptr<SurfaceGeometry> geometry() const;
  // Volume per solid and area per face, OpenCASCADE against the mesh.
  std::vector<GeometryCheck> volume_checks(const Mesh& mesh) const;
  std::vector<GeometryCheck> area_checks(const Mesh& mesh) const;
  // The common pieces of overlapping solids (after the full fuse).
  std::vector<SolidOverlap> overlaps() const;
  // OpenCASCADE's own check of the shape (BOPAlgo_ArgumentAnalyzer: sub-shapes that
  // cross, curves off their surfaces, kinks, ...), named by the faces they
  // lie on; empty when it finds the shape valid. Slow (10 s on
  // pythonocc_11752.stp's 1,018 faces), so asked only to explain a failure.
  std::string geometry_faults() const;

  struct Impl;

 private:
  // |tessellated / CAD - 1| per solid, its number's pieces together (a CAD
  // volume of 0: unknown, error 0).
  std::vector<double> volume_errors(const Mesh& surface) const;
  explicit CadModel(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

}  // namespace vd::cad
