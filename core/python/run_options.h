// The meshing options of the Python module (the command line's, as keyword
// arguments) and the way a long call runs: on a worker thread with the GIL
// released, while the calling thread watches for Ctrl-C and the caller's
// CancelToken and raises the cancel flag the core polls.
#pragma once

#include <atomic>
#include <functional>
#include <memory>
#include <string>

#include <pybind11/pybind11.h>

#include "cad/cad_mesher.h"
#include "mesh/error.h"
#include "pipeline/mesher.h"

namespace vd::python {

namespace py = pybind11;

// Shared with the worker, so that it outlives a caller that drops it.
struct CancelToken {
  std::shared_ptr<std::atomic<bool>> flag = std::make_shared<std::atomic<bool>>(false);
};

struct RunOptions {
  cad::CadMeshOptions cad;          // cad.mesh: the options of mesh_surface
  py::object progress;              // callable(phase: str) or None
  std::shared_ptr<std::atomic<bool>> token;  // from CancelToken, or null
};

// The flag of a `cancel` argument: None, or a CancelToken (else TypeError).
std::shared_ptr<std::atomic<bool>> cancel_flag(py::handle value);

// The keyword options shared by mesh_surface and mesh_cad; `cad_input`
// allows the CAD-only ones (deflection, planar_splits). Unknown names raise
// TypeError, out-of-range values ValueError, as the command line refuses them.
RunOptions parse_options(const py::kwargs& kwargs, bool cad_input);

// The docstring paragraph listing the options.
extern const char* const kOptionsDoc;

// Runs `work` (which must not touch Python objects) on a worker thread.
// Ctrl-C in the main thread raises KeyboardInterrupt once the core has
// stopped; a set CancelToken raises vdmesh.Cancelled; an exception from the
// progress callback stops the run and is re-raised.
MeshResult run_interruptible(RunOptions& options, const std::function<MeshResult(const MeshOptions&)>& work);

// The report as a dict: the JSON of `vdmesh mesh --report`, parsed.
py::dict report_dict(const MeshReport& report);

// Raised by run_interruptible for RecoveryError: carries the partial report
// (with missing_facets) and the surface they index (its points), which the
// exception translator attaches.
struct RecoveryWithReport : RecoveryError {
  RecoveryWithReport(const RecoveryError& e, MeshResult&& partial)
      : RecoveryError(e.what()), report(std::move(partial.report)), surface(std::move(partial.mesh)) {}
  MeshReport report;
  Mesh surface;
};

}  // namespace vd::python
