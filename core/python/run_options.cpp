#include "python/run_options.h"

#include <chrono>
#include <cmath>
#include <condition_variable>
#include <exception>
#include <limits>
#include <mutex>
#include <optional>
#include <set>
#include <thread>

#include "mesh/cancel.h"
#include "mesh/error.h"

namespace vd::python {
namespace {

std::string type_name(py::handle v) { return py::str(py::type::handle_of(v).attr("__name__")).cast<std::string>(); }

double number(py::handle v, const std::string& name) {
  if (PyBool_Check(v.ptr()) || PyUnicode_Check(v.ptr()))
    throw py::type_error("option " + name + ": expected a number, got " + type_name(v));
  double x = 0;
  try {
    x = v.cast<double>();
  } catch (const py::cast_error&) {
    throw py::type_error("option " + name + ": expected a number, got " + type_name(v));
  }
  if (!std::isfinite(x)) throw UsageError("option " + name + ": not a finite number");
  return x;
}

long long integer(py::handle v, const std::string& name) {
  if (PyBool_Check(v.ptr())) throw py::type_error("option " + name + ": expected an integer, got bool");
  try {
    return v.cast<long long>();
  } catch (const py::cast_error&) {
    PyErr_Clear();
    if (PyLong_Check(v.ptr())) throw UsageError("option " + name + ": " + py::str(v).cast<std::string>() + " is out of range");
    throw py::type_error("option " + name + ": expected an integer, got " + type_name(v));
  }
}

// An integer option kept in an int: checked before the cast (4294967297 became 1).
int int_option(py::handle v, const std::string& name) {
  const long long x = integer(v, name);
  if (x < std::numeric_limits<int>::min() || x > std::numeric_limits<int>::max())
    throw UsageError("option " + name + ": out of range");
  return static_cast<int>(x);
}

bool boolean(py::handle v, const std::string& name) {
  // numpy.bool_ comes from comparisons on arrays: accept it beside bool.
  if (!PyBool_Check(v.ptr()) && type_name(v) != "bool_")
    throw py::type_error("option " + name + ": expected True or False, got " + type_name(v));
  return v.cast<bool>();
}

void check(bool ok, const std::string& message) {
  if (!ok) throw UsageError(message);
}

}  // namespace

const char* const kOptionsDoc = R"(Options (keyword arguments; the command line's options of the same name):
    size (float, 0): target edge length; 0: surface input: from its own edges,
        graded; CAD input: bounding-box diagonal / 25 (reported), and on solids that
        touch no other and are thinner than a quarter of it, 4 x their mean
        thickness 2V/A on their faces
    gradation (float, 0.3): largest growth of the size per unit distance
    interior (bool, True): interior vertices; False is --no-interior
    surface_grading (float, 2; mesh_cad 0): with interior vertices, surface edges longer
        than this times the surface's graded size are split (flips inside faces between;
        on CAD input on the CAD faces); 0: off
    sliver_angle (float, 20; mesh_cad 10, then 20 when every tetrahedron reached 10):
        tetrahedra under this dihedral angle (deg) are slivers, removed or improved
    keep_slivers (bool, False): no sliver removal
    delaunay_surface (bool, False): the sliver pass keeps every surface facet a face
        of the Delaunay tetrahedralization of the output's vertices (--delaunay-surface;
        always so with interior=False)
    cautious (bool, False): interior vertices that take no surface facet, and no
        cap fold splits (what a run falls back to when the recovery with interior
        vertices stops)
    volume (str, "delaunay"): "advancing-front" builds the tetrahedra by the paper's
        advancing-front Delaunay from the facets (the same tetrahedra, slower)
    oracle (str, "dt"): facet Delaunayhood test, "dt", "lp" or "sphere"
    lp_limit (int, -1): largest LP the lp oracle solves (-1: no limit)
    flips (bool, True): False is --no-flips (only splits)
    flip_angle (float, 20): largest ridge angle (deg) a flip may create
    sharp_angle (float, 40): face ids of untagged input split where normals differ more (deg)
    seed (int, 1): the same input, options and seed give the same mesh
    threads (int, 0): threads for the parallel loops, 0 one per core; the mesh is the same
    shift (float, 1e-4): random shift relative to the local edge length, in [0, 0.1]
    max_passes (int, 200), max_added (int, -1: 20 x input vertices + 1000): Delaunayzation guards
    order (int, 1): 2 gives 10-node tetrahedra (mesh.tet_mid, mesh.triangle_mid); on CAD
        input the surface's mid-edge nodes lie on the CAD faces and edges
    progress (callable(str) or None): called with the name of each phase as it starts
        (on the worker thread, holding the GIL); an exception raised there stops the run
        and is re-raised by the call
    cancel (vdmesh.CancelToken or None): cancel.set() from any thread stops the run,
        which then raises vdmesh.Cancelled
  CAD input only:
    deflection (float, 0): chord height of the face tessellation (0: per face, size / 10,
        at most the mean thickness 2V/A / 50 of the solids on either side)
    planar_splits (bool, False): split vertices at chord mid-points instead of on the CAD geometry
    full_fuse (bool, False): fuse the solids in full at once, instead of gluing them first
        (as touching only) and fusing in full when the glued surface crosses itself
    angular_deflection (float, 20): OpenCASCADE's angular deflection (deg) on curved faces;
        unless it, deflection, max_passes or max_added is given, a recovery that stops at
        its guards is tried again: unsmoothed, then with one chord height everywhere
        (size / 500), then at 30 and 40 deg
    volume_tolerance (float, 0.4): with the automatic chord height, tessellate again finer
        while a solid's volume is off by more than this many per cent (0: once)
    smoothing (bool, True): move tessellation vertices inside faces, on the CAD face,
        where a corner is poor; False is --no-smoothing
    face_remesh (bool, True): mesh the faces anew inside their borders
        (Delaunay refinement); False is --no-face-remesh
)";

std::shared_ptr<std::atomic<bool>> cancel_flag(py::handle value) {
  if (value.is_none()) return nullptr;
  if (!py::isinstance<CancelToken>(value))
    throw py::type_error("option cancel: expected a vdmesh.CancelToken, got " + type_name(value));
  return value.cast<const CancelToken&>().flag;
}

RunOptions parse_options(const py::kwargs& kwargs, bool cad_input) {
  static const std::set<std::string> kCommon = {
      "size",     "gradation",  "interior",    "surface_grading",    "sliver_angle", "keep_slivers", "delaunay_surface", "cautious", "oracle",     "lp_limit", "volume",
      "flips",    "flip_angle", "sharp_angle", "seed",         "shift",        "max_passes", "max_added",
      "order",    "progress",   "cancel",      "threads"};
  static const std::set<std::string> kCad = {"deflection", "planar_splits", "full_fuse", "angular_deflection", "volume_tolerance",
                                             "smoothing", "face_remesh"};
  RunOptions run;
  MeshOptions& opt = run.cad.mesh;
  // The defaults of the entry point: mesh_surface's are not the CAD ones
  // that CadMeshOptions starts from (the sliver angle).
  opt = cad_input ? cad::cad_mesh_defaults() : MeshOptions{};
  opt.size.uniform = 0;
  for (const auto& [key, value] : kwargs) {
    const std::string name = key.cast<std::string>();
    if (!kCommon.count(name) && !(cad_input && kCad.count(name))) {
      const bool cad_only = kCad.count(name) > 0;
      throw py::type_error("unexpected keyword argument '" + name + "'" +
                           (cad_only ? " (an option of mesh_cad only)"
                                     : cad_input ? " (see help(vdmesh.mesh_cad))" : " (see help(vdmesh.mesh_surface))"));
    }
    if (name == "size") opt.size.uniform = number(value, name);
    else if (name == "gradation") opt.size.gradation = number(value, name);
    else if (name == "interior") opt.interior = boolean(value, name);
    else if (name == "surface_grading") opt.surface_grading = number(value, name);
    else if (name == "sliver_angle") {
      opt.slivers.sliver_angle_deg = number(value, name);
      opt.slivers.raised_angle_deg = 0;  // the angle given, and no other
    }
    else if (name == "keep_slivers") opt.remove_slivers = !boolean(value, name);
    else if (name == "delaunay_surface") opt.slivers.delaunay_surface = boolean(value, name);
    else if (name == "cautious") opt.cautious = boolean(value, name);
    else if (name == "volume") {
      if (!PyUnicode_Check(value.ptr())) throw py::type_error("option volume: expected a str, got " + type_name(value));
      const std::string method = value.cast<std::string>();
      check(method == "delaunay" || method == "advancing-front",
            "option volume: unknown method '" + method + "' (choose delaunay or advancing-front)");
      opt.volume = method == "delaunay" ? VolumeMethod::delaunay : VolumeMethod::advancing_front;
    } else if (name == "oracle") {
      if (!PyUnicode_Check(value.ptr())) throw py::type_error("option oracle: expected a str, got " + type_name(value));
      opt.oracle = value.cast<std::string>();
    } else if (name == "lp_limit") opt.oracle_options.lp_limit = int_option(value, name);
    else if (name == "flips") opt.delaunayzation.flips = boolean(value, name);
    else if (name == "flip_angle") opt.delaunayzation.flip_angle_deg = number(value, name);
    else if (name == "sharp_angle") opt.sharp_angle_deg = number(value, name);
    else if (name == "seed") {
      const long long s = integer(value, name);
      check(s >= 0, "option seed: must not be negative");
      opt.seed = static_cast<std::uint64_t>(s);
    } else if (name == "threads") {
      const long long t = integer(value, name);
      check(t >= 0 && t <= 1024, "option threads: must be in [0, 1024]");
      opt.threads = static_cast<int>(t);
    } else if (name == "shift") opt.shift = number(value, name);
    else if (name == "max_passes") {
      opt.delaunayzation.max_passes = int_option(value, name);
      run.cad.retry_angles_deg.clear();  // a guard given by hand decides
    } else if (name == "max_added") {
      opt.delaunayzation.max_added_vertices = int_option(value, name);
      run.cad.retry_angles_deg.clear();
    }
    else if (name == "order") {
      const long long order = integer(value, name);
      check(order == 1 || order == 2, "option order: must be 1 or 2");
      opt.order = static_cast<int>(order);
    }
    else if (name == "progress") {
      if (!value.is_none() && !PyCallable_Check(value.ptr()))
        throw py::type_error("option progress: expected a callable, got " + type_name(value));
      run.progress = py::reinterpret_borrow<py::object>(value);
    } else if (name == "cancel") {
      run.token = cancel_flag(value);
    } else if (name == "deflection") {
      run.cad.tessellation.deflection = number(value, name);
      run.cad.retry_angles_deg.clear();  // a tessellation given by hand is kept
    }
    else if (name == "planar_splits") run.cad.splits_on_geometry = !boolean(value, name);
    else if (name == "full_fuse")
      run.cad.fuse = boolean(value, name) ? cad::CadModel::Fuse::in_full : cad::CadModel::Fuse::glued_first;
    else if (name == "angular_deflection") {
      run.cad.tessellation.angle_deg = number(value, name);
      run.cad.retry_angles_deg.clear();
    }
    else if (name == "volume_tolerance") run.cad.tessellation.volume_tolerance = number(value, name) / 100;
    else if (name == "smoothing") run.cad.tessellation.smooth = boolean(value, name);
    else if (name == "face_remesh") run.cad.tessellation.remesh = boolean(value, name);
  }
  // The command line's checks, with the option names of this module.
  check(opt.size.uniform >= 0, "option size: must not be negative");
  check(opt.size.gradation > 0, "option gradation: must be positive");
  check(opt.surface_grading == 0 || opt.surface_grading >= 1, "option surface_grading: must be 0 or at least 1");
  check(opt.shift >= 0 && opt.shift <= 0.1, "option shift: must be in [0, 0.1]");
  check(opt.delaunayzation.flip_angle_deg >= 0 && opt.delaunayzation.flip_angle_deg <= 180,
        "option flip_angle: must be in [0, 180]");
  check(opt.oracle == "dt" || opt.oracle == "lp" || opt.oracle == "sphere",
        "option oracle: unknown oracle '" + opt.oracle + "' (choose dt, lp or sphere)");
  check(run.cad.tessellation.deflection == 0 || run.cad.tessellation.deflection >= cad::kSmallestDeflection,
        "option deflection: must be 0 (chosen per face) or at least 1e-7 (OpenCASCADE's precision)");
  check(run.cad.tessellation.angle_deg > 0 && run.cad.tessellation.angle_deg <= 90,
        "option angular_deflection: must be in (0, 90]");
  check(run.cad.tessellation.volume_tolerance >= 0, "option volume_tolerance: must not be negative");
  check(opt.delaunayzation.max_passes >= 0, "option max_passes: must not be negative");
  check(opt.delaunayzation.max_added_vertices >= -1, "option max_added: must not be negative (-1: the default)");
  check(opt.oracle_options.lp_limit == -1 || opt.oracle_options.lp_limit >= 1,
        "option lp_limit: must be positive (-1: no limit)");
  check(opt.slivers.sliver_angle_deg >= 0 && opt.slivers.sliver_angle_deg <= kLargestSliverAngleDeg,
        "option sliver_angle: must be in [0, 70.5] (no tetrahedron has all its dihedral angles over 70.53 deg)");
  check(opt.sharp_angle_deg >= 0 && opt.sharp_angle_deg <= 180, "option sharp_angle: must be in [0, 180]");
  return run;
}

namespace {

// What the worker and the watching thread share.
struct RunState {
  std::mutex mutex;
  std::condition_variable done_signal;
  bool done = false;
  std::optional<MeshResult> result;
  std::exception_ptr error;
  // An exception of the progress callback, kept until the watching thread
  // (which holds the GIL then) re-raises it.
  std::optional<py::error_already_set> callback_error;
};

}  // namespace

MeshResult run_interruptible(RunOptions& run, const std::function<MeshResult(const MeshOptions&)>& work) {
  auto state = std::make_shared<RunState>();
  // The run's own flag: Ctrl-C and the caller's token both raise it.
  auto stop = std::make_shared<std::atomic<bool>>(false);
  MeshOptions opt = run.cad.mesh;
  opt.cancel = stop.get();
  // A token set before the call stops the run at its first look (short
  // runs ended before the loop below first looked at the token, 20 of 20).
  if (run.token && run.token->load()) stop->store(true);
  if (run.progress && !run.progress.is_none()) {
    // A borrowed pointer (run.progress keeps it alive for the call): the core
    // copies its options, and copying a py::object would touch reference
    // counts without the GIL.
    PyObject* callback = run.progress.ptr();
    opt.progress = [callback, state, stop](const std::string& phase) {
      py::gil_scoped_acquire gil;
      try {
        py::handle fn(callback);
        fn(phase);
      } catch (py::error_already_set& e) {
        state->callback_error.emplace(std::move(e));
        stop->store(true);
        throw CancelledError();
      }
    };
  }

  std::thread worker([&work, opt, state]() {
    std::optional<MeshResult> result;
    std::exception_ptr error;
    try {
      result.emplace(work(opt));
    } catch (...) {
      error = std::current_exception();
    }
    std::lock_guard<std::mutex> lock(state->mutex);
    state->result = std::move(result);
    state->error = error;
    state->done = true;
    state->done_signal.notify_all();
  });

  std::optional<py::error_already_set> interrupt;
  for (;;) {
    {
      py::gil_scoped_release release;
      std::unique_lock<std::mutex> lock(state->mutex);
      if (state->done_signal.wait_for(lock, std::chrono::milliseconds(50), [&] { return state->done; })) break;
    }
    // Signals are handled only here, in the main thread holding the GIL; in
    // other threads PyErr_CheckSignals returns 0 and the token is the way.
    if (!interrupt && PyErr_CheckSignals() != 0) {
      interrupt.emplace();  // fetches the KeyboardInterrupt (or the handler's exception)
      stop->store(true);
    }
    if (run.token && run.token->load()) stop->store(true);
  }
  {
    py::gil_scoped_release release;
    worker.join();
  }
  // Python errors are re-raised here, with the GIL held. A run that ended
  // anyway after Ctrl-C still raises KeyboardInterrupt: the user asked to stop.
  if (state->callback_error) throw *state->callback_error;
  if (interrupt) throw *interrupt;
  if (state->error) std::rethrow_exception(state->error);  // CancelledError here: the token
  // A run that ended anyway after its token was set (in a phase that does
  // not look, such as the sliver pass) still raises: the caller asked to stop.
  if (run.token && run.token->load()) throw CancelledError();
  return std::move(*state->result);
}

py::dict report_dict(const MeshReport& report) {
  return py::module_::import("json").attr("loads")(report_json(report));
}

}  // namespace vd::python
