#include "pipeline/mesher.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <future>
#include <iterator>
#include <limits>
#include <map>
#include <memory>
#include <optional>
#include <unordered_map>

#include "delaunay/delaunay_tetrahedralization.h"
#include "mesh/error.h"
#include "mesh/memory.h"
#include "mesh/number_text.h"
#include "mesh/parallel.h"
#include "mesh/progress.h"
#include "mesh/size_budget.h"
#include "mesh/tet_faces.h"
#include "pipeline/input_facets.h"
#include "pipeline/missing_facets.h"
#include "surface/edge_map.h"
#include "surface/face_patches.h"
#include "surface/input_surface_geometry.h"
#include "surface/size_refinement.h"
#include "surface/validate_surface.h"
#include "volume/cap_vertices.h"
#include "volume/facet_takers.h"

namespace vd {
namespace {

// find_self_intersections on another thread, on its own copy of the surface.
class SelfIntersectionCheck {
 public:
  // On this thread now (throws at once) unless `beside` is set.
  void start(const Mesh& m, bool beside) {
    if (!beside) {
      throw_self_intersections(find_self_intersections(m));
      return;
    }
    auto copy = std::make_shared<Mesh>();
    copy->points = m.points;
    copy->triangles = m.triangles;
    // On this one thread: a second worker of its own took the core the
    // tetrahedralization runs on (three busy threads on two cores).
    result_ = std::async(std::launch::async, [copy, this] {
      std::vector<std::pair<int, int>> found = find_self_intersections(*copy, 20, 1);
      if (!found.empty()) found_ = true;
      return found;
    });
  }
  bool pending() const { return result_.valid(); }
  // Set as soon as a crossing is found (DelaunayzationOptions::abandon).
  const std::atomic<bool>* found_flag() const { return &found_; }
  // Waits for the test; throws its InputError when the surface crosses itself.
  void await_result() {
    if (result_.valid()) throw_self_intersections(result_.get());
  }

 private:
  std::atomic<bool> found_{false};
  std::future<std::vector<std::pair<int, int>>> result_;
};

class PhaseTimer {
 public:
  PhaseTimer(MeshReport& r, const MeshOptions& o) : report_(r), options_(o) {}
  ~PhaseTimer() { stop(); }
  void start(const std::string& phase) {
    stop();
    throw_if_cancelled(options_.cancel);
    phase_ = phase;
    clear_phase_fraction();
    if (options_.progress) options_.progress(phase);
    t0_ = std::chrono::steady_clock::now();
  }
  void stop() {
    if (phase_.empty()) return;
    const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0_).count();
    report_.seconds.emplace_back(phase_, s);
    const double peak = peak_resident_mib();
    if (peak > 0) report_.peak_mib.emplace_back(phase_, peak);
    phase_.clear();
  }

 private:
  MeshReport& report_;
  const MeshOptions& options_;
  std::string phase_;
  std::chrono::steady_clock::time_point t0_;
};

void accumulate(DelaunayzationResult& total, const DelaunayzationResult& pass) {
  total.passes += pass.passes;
  total.flips += pass.flips;
  total.splits += pass.splits;
  total.splits_on_chord += pass.splits_on_chord;
  total.splits_on_chord_for_volume += pass.splits_on_chord_for_volume;
  total.added_vertices += pass.added_vertices;
  total.added_facets += pass.added_facets;
  total.oracle_wrong += pass.oracle_wrong;
  total.shell_splits = total.shell_splits || pass.shell_splits;
  total.missing = pass.missing;
}

// The facets in one list and not the other, as sorted vertex triples.
std::vector<std::array<int, 3>> changed_facets(const std::vector<Triangle>& before, const std::vector<Triangle>& after) {
  const auto triples = [](const std::vector<Triangle>& facets) {
    std::vector<std::array<int, 3>> out;
    out.reserve(facets.size());
    for (const Triangle& t : facets) out.push_back(sorted_triple(t.v));
    std::sort(out.begin(), out.end());
    return out;
  };
  const std::vector<std::array<int, 3>> a = triples(before), b = triples(after);
  std::vector<std::array<int, 3>> out;
  std::set_symmetric_difference(a.begin(), a.end(), b.begin(), b.end(), std::back_inserter(out));
  return out;
}

}  // namespace

// Rounds of cap fold splits. On CAD input (with its splits on the faces, not
// --planar-splits) a mid-point goes onto the curved face and leaves new caps
// beside it: three rounds took the ring from 3.06 to
// 4.57 deg and the fusee from 0.63 to 1.70. On faceted input the mid-point
// stays on the edge, one round leaves no cap a second would split (the
// quality table the same but for the lever), and the second round's vertices
// on the lever's creases let the sliver pass slide one along a crease known
// to 1e-12 only, taking a facet off its plane (Slivers.SharedSurfaces).
constexpr int kCapFoldRoundsCad = 3;
// After them, rounds for the caps over a smooth border between two faces
// only (a fold edge on a CAD edge, which case A keeps, whose two facets'
// normals are within kSmoothBorderDeg): each split of such a fold beside a
// CAD vertex leaves the next cap on the half next to the vertex.
// gmsh_Block.stp's seam between the two halves of a cylinder (0.5 deg), at
// the corner with its top face, kept a 0.19 deg cap after three rounds
// (folds 0.8 and then 0.4 long) and none after a fourth: 3.82 deg. Every
// fold for two more rounds did that too, but took caxif_as1-oc-214.stp from
// 1.16 to 0.87 deg and the Exhaust from 303 to 466 tetrahedra under 10 deg;
// every fold on a border, the same (their folds are at interfaces and knife
// edges). With the smooth borders only (a bound of 1, 5 or 20 deg gave the
// same), the Block and one fold of the Exhaust (303 -> 299 under 10 deg)
// change, no other file of the CAD corpus.
constexpr int kBorderFoldRoundsCad = 2;
constexpr double kSmoothBorderDeg = 5.0;

namespace {

// Patience of the recoveries after the first while a cautious run is left
// (mesh_surface).
constexpr int kPatienceWithCautiousRetry = 8;

// When a recovery runs away, a face with at most this many facets missing
// is not where it ran away (the faces RecoveryError carries).
constexpr int kHandfulOnAFace = 10;

// Resident memory over which the freed tetrahedralization is handed back
// before the sliver pass (see there): the 125k box holds 27 MiB then, the
// 765k box and the elephant about 100, gmsh_simple_plane.brep 180.
constexpr double kHandBackFreedTetrahedralizationMiB = 64;

// Thrown by mesh_surface_once when a recovery after the first stops and a
// cautious run is left: the seconds spent.
struct LaterRecoveryStopped {
  double seconds = 0;
};

// Edges of the input on one facet only, each with its midpoint and facet.
// Allowed for cracks inside a region; where the regions come out open they
// are the likely cause, and where they are is what mends the surface: a CAD
// tessellation at chord height 1000 left 82 of them between gmsh_part.step's
// faces, and the message named only facets, all of them.
struct OpenEdge {
  Vec3 middle;
  int facet;
};

// "; the input has N edges on one facet only (...), e.g. near (x, y, z) on
// face F, ...": up to three places, on different faces where there are.
std::string open_edges_text(const std::vector<OpenEdge>& open, const Mesh& m) {
  if (open.empty()) return "";
  std::vector<const OpenEdge*> shown;
  std::vector<int> faces;
  for (const bool any_face : {false, true})
    for (const OpenEdge& e : open) {
      if (shown.size() == 3) break;
      const int face = m.triangles[e.facet].face;
      if (std::find(shown.begin(), shown.end(), &e) != shown.end()) continue;
      if (!any_face && std::find(faces.begin(), faces.end(), face) != faces.end()) continue;
      shown.push_back(&e);
      faces.push_back(face);
    }
  std::string text = "; the input has " + std::to_string(open.size()) +
                     " edges on one facet only (a gap in the surface, unless a crack inside a region), e.g.";
  for (size_t i = 0; i < shown.size(); ++i) {
    const Vec3& p = shown[i]->middle;
    text += std::string(i ? "," : "") + " near (" + number_text(p.x, "%.4g") + ", " + number_text(p.y, "%.4g") +
            ", " + number_text(p.z, "%.4g") + ") on facet " + std::to_string(shown[i]->facet);
    if (faces[i] != kNoFace) text += " of face " + std::to_string(faces[i]);
  }
  return text;
}

// `cautious`: interior vertices that take no surface facet, and no cap fold
// splits. `can_retry`: a cautious run is left after this one.
MeshResult mesh_surface_once(const Mesh& input, const MeshOptions& options, MeshResult* partial, bool cautious,
                             bool can_retry) {
  const auto started = std::chrono::steady_clock::now();
  MeshResult result;
  MeshReport& report = result.report;
  Mesh& m = result.mesh;
  PhaseTimer timer(report, options);
  report.input_vertices = static_cast<int>(input.points.size());
  report.input_facets = static_cast<int>(input.triangles.size());
  report.oracle = options.oracle;
  auto oracle = make_oracle(options.oracle, options.oracle_options);

  timer.start("validate");
  check_tags_and_sizes(input);
  set_thread_count(options.threads);
  m.points = input.points;
  m.point_size = input.point_size;
  m.triangles = input.triangles;
  m.region_names = input.region_names;
  m.face_names = input.face_names;
  m.face_groups = input.face_groups;
  m.region_points = input.region_points;
  const std::vector<int> kept = drop_unused_points(m);
  report.unused_input_vertices = static_cast<int>(std::count(kept.begin(), kept.end(), -1));
  report.welded_input_vertices = weld_coincident_points(m);
  drop_unused_points(m);
  // One edge map while the facets stay as they are (it was built five times,
  // a seventh of a surface-only run).
  std::optional<EdgeMap> edges(m.triangles);
  // The self-intersection test, the longest part of validation, runs on a
  // second thread (when there is one) beside the refinement, the shift, the
  // tetrahedralization and the first recovery, on a copy of the facets; its
  // answer is awaited before anything is built on the recovered surface,
  // and a recovery it makes moot is abandoned (SelfIntersectionCheck).
  SelfIntersectionCheck crossings;
  std::vector<OpenEdge> open_edges;
  if (options.validate) {
    const SurfaceCheck check = validate_surface(m, &*edges, /*self_intersections=*/false);
    for (const auto& [a, b] : check.open_edges)
      open_edges.push_back({0.5 * (m.points[a] + m.points[b]), edges->facets(a, b)[0]});
    crossings.start(m, thread_count() > 1);
  }
  const bool none_given =
      std::all_of(m.triangles.begin(), m.triangles.end(), [](const Triangle& t) { return t.face == kNoFace; });
  // Face ids of the input's own (InputSurfaceGeometry), not patches.
  const bool faces_given = !none_given && !options.faces_are_patches;
  if (!m.has_face_tags()) {
    // The facets without a face get their patch's number. When no facet had
    // one, the input's face names and groups name other faces.
    report.face_patches_assigned = assign_face_patches(m, options.sharp_angle_deg, &*edges);
    if (none_given) {
      m.face_names.clear();
      m.face_groups.clear();
    }
  }
  // Faceted input: the sliver pass slides vertices of curved faces on the
  // input facets (input_surface_geometry.h), as it does on CAD faces.
  std::optional<InputSurfaceGeometry> input_geometry;
  if (!options.delaunayzation.geometry && options.interior && options.delaunayzation.flips && options.remove_slivers &&
      options.slivers.moves)
    input_geometry.emplace(m, faces_given);
  if (options.size.uniform > 0) {
    // Before the refinement makes them: a size far below the model's (a unit
    // mix-up) is refused, not run out of memory.
    double area = 0, volume = 0;
    const Vec3 o = m.points.empty() ? Vec3{} : m.points.front();
    for (const Triangle& t : m.triangles) {
      area += facet_area(m.points, t);
      volume += tet_volume(o, m.points[t.v[0]], m.points[t.v[1]], m.points[t.v[2]]);
    }
    check_size_budget(area, volume, options.size.uniform, options.interior,
                      "size " + number_text(options.size.uniform, "%g"));
  }
  {
    // Needles and caps on the input make every tetrahedron on them flat; the
    // graded refinement (volume meshing only: the paper's surface recovery
    // stays as it is) grades the edges down to the shortest edges around.
    GradedSizes graded;
    std::optional<SizeField> through_space;
    const bool grade = options.interior && options.surface_grading > 0 && options.delaunayzation.flips;
    if (grade || options.size.uniform > 0 || !m.point_size.empty()) timer.start("surface refinement");
    if (grade) {
      graded.gradation = options.size.gradation;
      graded.factor = options.surface_grading;
      graded.flip_ridge_deg = options.delaunayzation.flip_angle_deg;
      graded.size = graded_edge_sizes(m, graded.gradation);
      // Graded through space too, not only along the edges: a fine surface
      // near big facets of another part (a horizon 0.05 from the side of a
      // box of 1.0 facets) fills the gap with small interior vertices, and
      // each of them makes a flat tetrahedron with a big facet unless that is
      // split too (cgal_horizons_in_domain: 154 -> 5 tetrahedra under 10 deg,
      // sliver pass 3.1 -> 0.07 s).
      through_space.emplace(m, graded.size, SizeFieldOptions{0.0, graded.gradation});
      for (size_t v = 0; v < m.points.size(); ++v)
        if (graded.size[v] > 0) graded.size[v] = std::min(graded.size[v], through_space->at(m.points[v]));
      graded.in_space = [&through_space](const Vec3& p) { return through_space->at(p); };
      // The limit for input angles that excuse slivers.
      graded.sharp_corner = sharp_face_corners(m, 20.0);
    }
    const SizeRefinementStats refined = refine_surface_to_size(m, options.size.uniform, grade ? &graded : nullptr);
    report.size_splits = refined.splits;
    report.size_flips = refined.flips;
  }
  // Splits and flips both change the facets the edge map was built from.
  if (report.size_splits > 0 || report.size_flips > 0) edges.reset();

  timer.start("random shift");
  // On CAD input the surface vertices go back after the volume (below).
  std::vector<Vec3> unshifted, shifted;
  if (options.shift > 0) {
    if (options.delaunayzation.geometry) unshifted = m.points;
    report.shift = random_shift(m, {options.shift, options.seed, options.sharp_angle_deg}, edges ? &*edges : nullptr);
    if (options.delaunayzation.geometry) shifted = m.points;
  }

  timer.start("tetrahedralize");
  // Owned apart so that the sliver pass can free it once it is done with it.
  auto dt_owner = std::make_unique<DelaunayTetrahedralization>();
  DelaunayTetrahedralization& dt = *dt_owner;
  dt.insert(m.points, 0, options.cancel);
  if (dt.number_of_vertices() != static_cast<int>(m.points.size()))
    throw InputError("the input has coincident vertices (" +
                     std::to_string(m.points.size() - dt.number_of_vertices()) + " duplicates)");
  // A surface in one plane encloses nothing, and its tetrahedralization has
  // no tetrahedra to look facets up in (a square sheet alone crashed there).
  if (dt.dimension() < 3)
    throw InputError("the input's " + std::to_string(m.points.size()) + " vertices all lie " +
                     (dt.dimension() == 2 ? "in one plane" : dt.dimension() == 1 ? "on one line" : "at one point") +
                     ": its facets enclose no volume");
  oracle->attach(&m.points, &dt);
  DelaunayzationOptions dopt = options.delaunayzation;
  dopt.seed = options.seed;
  dopt.cancel = options.cancel;
  dopt.abandon = crossings.found_flag();

  auto recover = [&](const char* phase) {
    timer.start(phase);
    // The shift moves points only: the edge map of the validation still
    // holds, for the first recovery (a thirtieth of a surface-only run).
    const DelaunayzationResult pass = delaunayize(m, dt, *oracle, dopt, edges ? &*edges : nullptr);
    edges.reset();
    accumulate(report.delaunayzation, pass);
    report.oracle_stats = oracle->stats();
    report.added_surface_vertices = report.delaunayzation.added_vertices;
    report.added_surface_facets =
        static_cast<int>(m.triangles.size()) + report.hole_facets_dropped - report.input_facets;
    report.delaunayzation.added_facets = report.added_surface_facets;
    report.output_vertices = static_cast<int>(m.points.size());
    report.output_facets = static_cast<int>(m.triangles.size());
    report.complete = pass.complete();
    if (report.complete) return;
    crossings.await_result();  // a surface that crosses itself is bad input, not a stopped recovery
    timer.stop();
    std::map<int, int> missing_by_face;
    for (int f : pass.missing) {
      report.missing_facets.push_back(m.triangles[f].v);
      ++missing_by_face[m.triangles[f].face];
    }
    // The faces where recovery stopped; when it ran away, those with more
    // than a handful of facets missing. A few facets stay missing on faces
    // far from where it ran away, where the passes were still at work (on
    // gmsh_simple_plane.brep, 6 or 7 on each nose cone against 1,231 on the
    // fuselage), and the solids there are better not held
    // (TessellationChain). A share of the missing ones instead freed faces
    // next to where it ran away, and recovery on the uniform chords then
    // stopped on simple_plane at 0.6 times its size (1 %) or twice (5 %).
    std::vector<int> missing_faces;
    for (const auto& [face, count] : missing_by_face)
      if (!pass.ran_away || count > kHandfulOnAFace) missing_faces.push_back(face);
    if (partial) *partial = result;
    throw RecoveryError(std::to_string(report.missing_facets.size()) + " facets could not be made Delaunay " +
                            (pass.ran_away ? "(the recovery ran away: " : "within the guards (") +
                            std::to_string(report.delaunayzation.passes) + " passes, " +
                            std::to_string(report.delaunayzation.added_vertices) + " added vertices); " +
                            where_facets_are_missing(m, pass.missing),
                        missing_faces, pass.ran_away);
  };

  // With interior vertices, a first recovery against the surface vertices
  // alone gives the regions, so that candidates are located exactly (point
  // location in the tetrahedralization) instead of by ray casting; the second
  // recovery is the paper's, against all vertices.
  try {
    recover("delaunayzation");
  } catch (const RecoveryError& e) {
    // A faceted surface with a gap whose first recovery stopped is bad
    // input, and the gap is what to say: a cube with a vertex doubled 1e-9
    // away (a crack of 8 edges) ended in exit 4 naming 1,010 missing facets
    // only (a surface tester, 2026-11-30). The later recoveries have their
    // own ways out (an undone fold round, the cautious run), and a CAD
    // tessellation its chain.
    if (open_edges.empty() || options.tessellated) throw;
    throw InputError(std::string("the surface is open and its recovery stopped: ") + e.what() +
                     open_edges_text(open_edges, m));
  }
  // Only the first recovery is stopped for running away alone: the later
  // ones have their own ways out (give_up_early, an undone fold round).
  dopt.stop_running_away = false;
  if (crossings.pending()) {
    timer.start("self-intersections (awaited)");
    crossings.await_result();
  }
  timer.start("volume");
  try {
    report.regions = build_region_tetrahedra(m, dt);
    const int facets = static_cast<int>(m.triangles.size());
    if (!report.regions.regions_from_tags && apply_region_points(m, dt)) {
      report.hole_facets_dropped = facets - static_cast<int>(m.triangles.size());
      if (m.triangles.empty())
        throw InputError("the hole points leave no region: every region of the surface holds a hole point");
      report.regions = build_region_tetrahedra(m, dt);
      report.regions.regions_from_tags = false;  // the points named them, not the input's tags
    }
  } catch (const FacetsError& e) {
    // Found on a surface the user never saw: named by the input's facets
    // (`vdmesh mesh cgal_complex_patch-13.off --size 2.26` said "2522
    // facets" of a 232-facet patch, by the refined surface's numbers).
    const bool refined = report.size_splits > 0 || report.size_flips > 0;
    if (!refined && report.delaunayzation.flips == 0 && report.delaunayzation.splits == 0)
      throw InputError(e.what() + open_edges_text(open_edges, m));
    throw InputError(e.describe(input_facets_under(input, m, e.facets())) +
                     " (numbered as in the input; found on the surface as " + (refined ? "refined" : "recovered") +
                     ", on " + std::to_string(e.facets().size()) + " of its " + std::to_string(m.triangles.size()) +
                     " facets)" + open_edges_text(open_edges, m));
  }

  // For the cap vertices and the sliver pass. Case A moves the surface off
  // the input on curved faces; with cases B and C it gains little above a
  // fraction of a degree (slivers_test).
  SliverOptions sliver_options = options.slivers;
  sliver_options.ridge_angle_deg = std::min(sliver_options.ridge_angle_deg, options.delaunayzation.flip_angle_deg);
  // --no-flips keeps the input's shape: case A then replaces only facets of
  // one plane (over a ridge of 0.1 deg it took 6.4 % off a slab 0.003 thick
  // until 2026-11-30).
  if (!options.delaunayzation.flips) sliver_options.ridge_angle_deg = 0;
  sliver_options.face_chord_height = options.delaunayzation.face_flip_offset;
  sliver_options.chord_height = options.delaunayzation.max_flip_offset;
  sliver_options.flip_ridge_deg = options.delaunayzation.flip_angle_deg;
  // Moves on curved CAD faces change the surface's chords: not with --no-flips.
  if (options.delaunayzation.flips)
    sliver_options.geometry = options.delaunayzation.geometry ? options.delaunayzation.geometry
                              : input_geometry                ? &*input_geometry
                                                              : nullptr;
  // Without interior vertices the run's product is the recovered surface,
  // a conforming Delaunay one (issue 2): the sliver pass keeps it so.
  if (!options.interior) sliver_options.delaunay_surface = true, sliver_options.inserts = false;
  if (options.interior) {
    // The size field and the region lookup are a phase of their own: they
    // do not look at the cancel flag, and a Cancel during "interior
    // vertices" should meet the candidate loop, which does.
    timer.start("size field");
    const SizeField size(m, options.size);
    report.smallest_size = size.smallest();
    InteriorOptions iopt = options.interior_options;
    iopt.seed = options.seed;
    iopt.cancel = options.cancel;
    // Cautious: no candidate may take a facet out of the tetrahedralization.
    std::optional<FacetTakers> takers;
    if (cautious) {
      takers.emplace(m, dt);
      iopt.takes_a_facet = [&takers](const Vec3& p) { return takers->takes_a_facet(p); };
    }
    timer.start(cautious ? "interior vertices sparing the facets" : "interior vertices");
    // A point's region is the label of the tetrahedron it falls in.
    std::vector<int> interior_regions;
    const std::vector<Vec3> interior = generate_interior_vertices(
        m, size, [&dt](const Vec3& p) { return dt.label_at(p); }, iopt, report.interior, &interior_regions);
    report.interior_vertices = static_cast<long>(interior.size());
    // Vertices from..end are in dt now: the oracle is told, and none may
    // have fallen onto an existing one.
    auto added_to_dt = [&](int from, const char* what) {
      for (int id = from; id < static_cast<int>(m.points.size()); ++id) oracle->vertex_added(id);
      if (dt.number_of_vertices() != static_cast<int>(m.points.size()))
        throw std::runtime_error(std::string(what) + " coincides with another vertex");
    };
    const bool from_tags = report.regions.regions_from_tags;  // the first pass set the tags
    // Vertices from..end of m.points into dt, then the paper's recovery
    // against all vertices and the regions again. When the new vertices are
    // inside regions (`regions`: each one's) and recovery found every facet
    // still a face, none was ever taken (a face once gone does not come back
    // with more vertices), so each new tetrahedron lies in the region of its
    // new vertex: labelled so, without building the regions again (a tenth
    // of the 6.6M box's run).
    auto recover_with = [&](int from, const char* what, const char* insert_phase, const char* recovery_phase,
                            const char* volume_phase, const std::vector<int>* regions,
                            const std::vector<Triangle>* facets_before = nullptr) {
      timer.start(insert_phase);
      dt.insert(m.points, from, options.cancel);
      added_to_dt(from, what);
      const DelaunayzationResult before = report.delaunayzation;
      recover(recovery_phase);
      timer.start(volume_phase);
      const bool surface_kept = report.delaunayzation.flips == before.flips &&
                                report.delaunayzation.added_vertices == before.added_vertices;
      // Labelled in place, not built again: the tetrahedra of new interior
      // vertices take their vertex's region; after a cap fold round (a few
      // facets changed: its splits and what their recovery did) those new
      // or beside a changed facet are labelled again (a full build was 0.23
      // to 0.37 s of gmsh_simple_plane.brep's run each time, four times).
      const bool by_new_vertices = regions && surface_kept;
      if (by_new_vertices) dt.label_new_cells(from, *regions);
      if (by_new_vertices ||
          (facets_before && dt.relabel_changed_cells(m, changed_facets(*facets_before, m.triangles)))) {
        // The old list freed first: the two side by side were the run's peak.
        m.tets = std::vector<Tetrahedron>();
        m.tets = dt.labelled_cells(&report.regions.tets_in_exterior);
        report.regions.labelled_by_new_vertices = by_new_vertices;
      } else {
        report.regions = build_region_tetrahedra(m, dt);
        report.regions.regions_from_tags = from_tags;
      }
    };
    const int first = static_cast<int>(m.points.size());
    m.points.insert(m.points.end(), interior.begin(), interior.end());
    if (!m.point_size.empty()) m.point_size.resize(m.points.size(), 0.0);
    // The recoveries after the first one (with interior vertices, after cap
    // fold splits) are given up, while a cautious run is left, when they
    // make no headway or add more vertices than the surface has: on the
    // plane the one after cap fold splits went on taking a few facets off
    // each pass while adding about 1,400 vertices a pass.
    auto give_up_early = [&](bool early) {
      if (early) {
        dopt.patience_passes = kPatienceWithCautiousRetry;
        const int own_guard = std::max(1000, first);
        if (dopt.max_added_vertices < 0 || dopt.max_added_vertices > own_guard) dopt.max_added_vertices = own_guard;
      } else {
        dopt.patience_passes = options.delaunayzation.patience_passes;
        dopt.max_added_vertices = options.delaunayzation.max_added_vertices;
      }
    };
    auto recover_or_give_up = [&](int from, const char* what, const char* insert_phase, const char* recovery_phase,
                                  const char* volume_phase, const std::vector<int>* regions) {
      give_up_early(can_retry);
      try {
        recover_with(from, what, insert_phase, recovery_phase, volume_phase, regions);
      } catch (const RecoveryError&) {
        if (!can_retry) throw;
        throw LaterRecoveryStopped{
            std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count()};
      }
      give_up_early(false);
    };
    recover_or_give_up(first, "an interior vertex", "insert interior vertices", "delaunayzation with interior vertices",
                       "volume with interior vertices", &interior_regions);
    if (options.remove_slivers) {
      // Flat tetrahedra held by two facets over a fold: the sliver pass
      // cannot reach them, a vertex inside the region can.
      timer.start("cap vertices");
      std::vector<std::array<int, 2>> refused_folds;
      auto open_caps = [&] {
        const bool on_cad = options.delaunayzation.geometry != nullptr;
        const std::vector<CapPoint> caps =
            cap_breaking_points(m, dt, sliver_options.sliver_angle_deg, sliver_options.ridge_angle_deg,
                                on_cad ? kCapPointClearanceCad : kCapPointClearance);
        const int first_cap = static_cast<int>(m.points.size());
        const int kept = caps.empty() ? 0
                                      : insert_cap_vertices(m, dt, caps, &refused_folds,
                                                            &report.interior.cap_points_fallback, /*refuse_unfair=*/on_cad);
        report.interior.cap_points_refused += static_cast<long>(caps.size()) - kept;
        if (kept > 0) {
          added_to_dt(first_cap, "a cap vertex");
          report.interior.cap_points += kept;
          report.interior_vertices += kept;
          report.output_vertices = static_cast<int>(m.points.size());
          // Every facet is still a Delaunay face (insert_cap_vertices kept
          // it so): no recovery, and the new tetrahedra took their region's
          // label.
          timer.start("volume with cap vertices");
          m.tets = std::vector<Tetrahedron>();  // freed first, as above
          m.tets = dt.labelled_cells();
        }
      };
      open_caps();
      // Caps no point can open without taking a facet: their fold edges are
      // split on the surface (on CAD input, onto the faces as recovery's
      // splits), recovered, and the caps looked for again.
      const int fold_rounds =
          cautious ? 0 : options.delaunayzation.geometry ? kCapFoldRoundsCad + kBorderFoldRoundsCad : 1;
      for (int round = 0; round < fold_rounds; ++round) {
        if (round >= kCapFoldRoundsCad) {
          const EdgeFacetPairs adjacency(m.triangles);
          // Two facets of two faces that meet smoothly there.
          const double cos_smooth = std::cos(kSmoothBorderDeg * M_PI / 180.0);
          const auto on_a_smooth_border = [&](const std::array<int, 2>& fold) {
            const std::vector<int> sharing = adjacency.facets(edge_key(fold[0], fold[1]));
            if (sharing.size() != 2) return false;
            const Triangle &a = m.triangles[sharing[0]], &b = m.triangles[sharing[1]];
            return a.face != b.face && dot(facet_normal(m.points, a), facet_normal(m.points, b)) >= cos_smooth;
          };
          refused_folds.erase(std::remove_if(refused_folds.begin(), refused_folds.end(),
                                             [&](const auto& fold) { return !on_a_smooth_border(fold); }),
                              refused_folds.end());
        }
        if (refused_folds.empty()) break;
        // A round whose recovery stops is undone, not the whole run: the
        // mesh before it is complete, and the cautious run that followed
        // has no fold splits at all (gmsh_simple_plane.brep's second round
        // ran away at the wing roots, and the cautious run took a third of
        // the time). Vertices are only appended meanwhile.
        const size_t points_before = m.points.size(), sizes_before = m.point_size.size();
        const std::vector<Triangle> facets_before = m.triangles;
        const MeshReport report_before = report;
        timer.start("cap fold splits");
        const int first_split = static_cast<int>(m.points.size());
        report.interior.cap_folds_split += split_cap_folds(m, refused_folds, options.delaunayzation.geometry,
                                                         &report.interior.cap_folds_at_sharp_corners,
                                                         options.delaunayzation.volume_limit);
        refused_folds.clear();
        give_up_early(true);
        try {
          recover_with(first_split, "a cap fold's mid-point", "insert cap fold splits",
                       "delaunayzation after cap fold splits", "volume after cap fold splits", nullptr,
                       &facets_before);
        } catch (const RecoveryError&) {
          timer.start("undo the cap fold round");
          m.points.resize(points_before);
          m.point_size.resize(sizes_before);
          m.triangles = facets_before;
          auto seconds = std::move(report.seconds);
          auto peaks = std::move(report.peak_mib);
          report = report_before;
          report.seconds = std::move(seconds);
          report.peak_mib = std::move(peaks);
          report.interior.cap_fold_round_undone = true;
          dt.clear();
          dt.insert(m.points, 0, options.cancel);
          oracle->attach(&m.points, &dt);
          // Every facet was a face of the tetrahedralization of these
          // vertices (unique: CGAL's symbolic perturbation), so this finds
          // them all in one pass.
          recover("delaunayzation after the undone round");
          timer.start("volume after the undone round");
          report.regions = build_region_tetrahedra(m, dt);
          report.regions.regions_from_tags = from_tags;
          break;
        }
        give_up_early(false);
        timer.start("cap vertices after fold splits");
        open_caps();
      }
    }
  }
  if (options.volume == VolumeMethod::advancing_front) {
    // The paper's way to the same tetrahedra: from the facets inwards, with
    // no use of the tetrahedralization (which the oracle and the regions
    // above needed, and the sliver pass's facet apexes still do).
    timer.start("advancing front");
    m.tets = advancing_front_tetrahedra(m, report.front, options.cancel);
    report.advancing_front = true;
  }
  if (options.remove_slivers) {
    timer.start("slivers");
    // Small runs keep the freed tetrahedralization's pages (below), and the
    // complex reuses them: the witnesses are then built on this thread too.
    const bool hand_back = resident_mib() > kHandBackFreedTetrahedralizationMiB;
    sliver_options.witnesses_beside = hand_back;
    report.slivers = remove_slivers(
        m, sliver_options, [&dt](const std::vector<Triangle>& t) { return dt.facet_apexes(t); }, &report.quality,
        [&dt_owner, hand_back] {
          dt_owner.reset();  // nothing below looks at dt
          // The freed tetrahedralization is handed back only when the run
          // holds much: the pages the pass's complex and witnesses then take
          // again cost a fault each, about 20 us on the 2-CPU VMs measured
          // (on the 125k box 2,350 faults, a tenth of its run; its peak is
          // 25-28 MiB either way, the complex taking the tetrahedra over),
          // while in large runs the complex may not fit in the freed blocks
          // and stacks beside them (gmsh_simple_plane.brep: 183 MiB with
          // the pages handed back, 212 without).
          if (hand_back) return_free_memory();
        });
    report.output_facets = static_cast<int>(m.triangles.size());
    report.interior_vertices += report.slivers.insertions;
    report.output_vertices = static_cast<int>(m.points.size());
  }
  // After the sliver pass, whose facet witnesses are the shifted points'
  // Delaunay tetrahedra; the quality figures are then the output's.
  if (!unshifted.empty()) {
    timer.start("unshift surface");
    report.shift.restored = restore_surface_positions(m, unshifted, shifted, sliver_options.sliver_angle_deg);
  }
  if (!options.remove_slivers || report.shift.restored > 0) {
    timer.start("quality");
    report.quality = summarize_quality(m, report.slivers.angle_deg);
    if (options.remove_slivers) {
      report.slivers.min_dihedral_after_deg = report.quality.min_dihedral_deg;
      report.slivers.below_5_after = report.quality.below_5_deg;
      report.slivers.below_10_after = report.quality.below_10_deg;
      report.slivers.slivers_after = report.quality.below_asked_deg;
    }
  }
  for (const Tetrahedron& t : m.tets) {
    if (t.region >= static_cast<int>(report.tets_per_region.size())) report.tets_per_region.resize(t.region + 1, 0);
    ++report.tets_per_region[t.region];
  }

  // The vertices of facets a hole dropped are in no element now: a solver
  // would take them for loose nodes.
  if (report.hole_facets_dropped > 0) {
    drop_unused_points(m);
    report.output_vertices = static_cast<int>(m.points.size());
    report.output_facets = static_cast<int>(m.triangles.size());
  }
  if (options.order == 2) {
    // After the quality figures: they are those of the straight elements.
    timer.start("second order");
    report.second_order = make_second_order(m, options.delaunayzation.geometry);
  }
  timer.stop();
  return result;
}

}  // namespace

// A recovery after the first can run away where the model has thin wedges:
// gmsh_simple_plane.brep at --deflection 0.001 recovers its surface alone
// and with interior vertices, then the recovery after the cap fold splits
// went on to the guard (89,326 facets missing at the wing's trailing edge
// root, 136k vertices added). When such a recovery makes no headway, the
// run is made again cautiously: no cap fold splits, and interior vertices
// that take no surface facet out of the tetrahedralization before they go in
// (volume/facet_takers.h, asked of each candidate that passed the other
// tests, which a run that succeeds does not pay for).
void check_mesh_options(const MeshOptions& o) {
  auto in = [](double v, double lo, double hi) { return std::isfinite(v) && v >= lo && v <= hi; };
  auto require = [](bool ok, const std::string& what) {
    if (!ok) throw UsageError("MeshOptions: " + what);
  };
  require(in(o.size.uniform, 0, std::numeric_limits<double>::max()), "size.uniform must be a finite number >= 0 (0: none), not " +
                                                                        number_text(o.size.uniform, "%g"));
  require(std::isfinite(o.size.gradation) && o.size.gradation > 0,
          "size.gradation must be positive, not " + number_text(o.size.gradation, "%g"));
  require(o.surface_grading == 0 || in(o.surface_grading, 1, std::numeric_limits<double>::max()),
          "surface_grading must be 0 or at least 1");
  require(in(o.shift, 0, 0.1), "shift must be in [0, 0.1]");
  require(in(o.delaunayzation.flip_angle_deg, 0, 180), "delaunayzation.flip_angle_deg must be in [0, 180]");
  require(in(o.slivers.sliver_angle_deg, 0, kLargestSliverAngleDeg), "slivers.sliver_angle_deg must be in [0, 70.5]");
  require(in(o.sharp_angle_deg, 0, 180), "sharp_angle_deg must be in [0, 180]");
  require(o.threads >= 0 && o.threads <= 1024, "threads must be in [0, 1024] (0: one per core)");
  require(o.order == 1 || o.order == 2, "order must be 1 or 2");
  require(o.delaunayzation.max_passes >= 0, "delaunayzation.max_passes must not be negative");
}

MeshResult mesh_surface(const Mesh& input, const MeshOptions& options, MeshResult* partial) {
  check_mesh_options(options);
  auto run = [&]() {
    if (options.cautious && options.interior) return mesh_surface_once(input, options, partial, true, false);
    try {
      return mesh_surface_once(input, options, partial, false, options.interior);
    } catch (const LaterRecoveryStopped& stopped) {
      MeshResult result = mesh_surface_once(input, options, partial, true, false);
      result.report.interior.cautious_retry = true;
      result.report.seconds.insert(result.report.seconds.begin(), {"run given up (a later recovery)", stopped.seconds});
      return result;
    }
  };
  MeshResult result = run();
  // A flag raised in a phase that does not look (the sliver pass, the
  // volume step) still ends the call without a mesh, as promised: the C++
  // caller got the finished mesh back until 2026-11-30 (Python checked).
  throw_if_cancelled(options.cancel);
  return result;
}

}  // namespace vd
