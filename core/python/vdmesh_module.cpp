// The Python module `vdmesh`: the core's mesher, CAD mesher and converters
// for Python (and FreeCAD) users. Meshes come and go as numpy arrays; the
// report is the dict of `vdmesh mesh --report`. Meshing runs on a worker
// thread with the GIL released and stops on Ctrl-C (run_options.h).
#include <cmath>

#include <pybind11/functional.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <string>

#include "cad/cad_mesher.h"
#include "cad/cad_model.h"
#include "converters/registry.h"
#include "mesh/cancel.h"
#include "mesh/error.h"
#include "mesh/parallel.h"
#include "python/mesh_arrays.h"
#include "python/run_options.h"

#ifndef VDMESH_VERSION
#define VDMESH_VERSION "unknown"
#endif

namespace py = pybind11;
using namespace pybind11::literals;

namespace vd::python {
namespace {

// The module's exception classes (kept for the life of the process, as the
// module is never unloaded).
PyObject* g_error = nullptr;
PyObject* g_input_error = nullptr;
PyObject* g_recovery_error = nullptr;
PyObject* g_cancelled = nullptr;
PyObject* g_file_error = nullptr;
PyObject* g_usage_error = nullptr;

PyObject* add_exception(py::module_& m, const char* name, const char* doc, py::tuple bases) {
  const std::string qualified = std::string("vdmesh.") + name;
  PyObject* type = PyErr_NewExceptionWithDoc(qualified.c_str(), doc, bases.ptr(), nullptr);
  if (!type) throw py::error_already_set();
  m.add_object(name, py::handle(type));
  return type;
}

void register_exceptions(py::module_& m) {
  g_error = add_exception(m, "Error", "Base class of the errors vdmesh raises.",
                          py::make_tuple(py::handle(PyExc_Exception)));
  g_input_error = add_exception(
      m, "InputError",
      "Bad input: an unreadable or malformed file, or an invalid surface (open, self-intersecting, degenerate, "
      "contradicting region tags). The message names the file and line, or the facets (exit code 3 of the "
      "command line).",
      py::make_tuple(py::handle(g_error), py::handle(PyExc_ValueError)));
  g_recovery_error = add_exception(
      m, "RecoveryError",
      "Some facets could not be made Delaunay within the guards (exit code 4 of the command line). The attribute "
      "`report` holds the report of the run so far, with the vertex ids of the facets still missing in "
      "report['missing_facets']; `mesh` the surface they index (its points and facets at that time).",
      py::make_tuple(py::handle(g_error), py::handle(PyExc_RuntimeError)));
  g_file_error = add_exception(
      m, "FileError",
      "A file that could not be opened, read or written: an OSError (errno, filename; a missing file has errno "
      "ENOENT) and a vdmesh.InputError.",
      py::make_tuple(py::handle(PyExc_OSError), py::handle(g_input_error)));
  g_cancelled = add_exception(m, "Cancelled", "The run was stopped through its CancelToken; there is no result.",
                              py::make_tuple(py::handle(g_error)));
  // A ValueError as before, and a vdmesh.Error like the others (an unknown
  // file extension was a plain ValueError, 2026-11-30).
  g_usage_error = add_exception(
      m, "UsageError",
      "Bad use: an option or argument out of its range, arrays that do not fit together, an unknown file "
      "extension (exit code 2 of the command line). Also a ValueError.",
      py::make_tuple(py::handle(g_error), py::handle(PyExc_ValueError)));
  // Messages and paths may hold a file name that is no UTF-8 (bytes paths):
  // decoded with surrogateescape, as Python decodes such names, where
  // PyErr_SetString lost the message and the path raised UnicodeDecodeError.
  static const auto text = [](const std::string& s) {
    return py::reinterpret_steal<py::object>(
        PyUnicode_DecodeUTF8(s.data(), static_cast<Py_ssize_t>(s.size()), "surrogateescape"));
  };
  static const auto set_error = [](PyObject* type, const char* what) { PyErr_SetObject(type, text(what).ptr()); };
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const RecoveryWithReport& e) {
      py::object error = py::handle(g_recovery_error)(text(e.what()));
      error.attr("report") = report_dict(e.report);
      error.attr("mesh") = py::cast(e.surface);
      PyErr_SetObject(g_recovery_error, error.ptr());
    } catch (const RecoveryError& e) {
      set_error(g_recovery_error, e.what());
    } catch (const FileError& e) {
      // OSError's own text: "[Errno 2] cannot write: No such file or directory: 'path'".
      std::string message = e.what();
      const std::string named = e.path() + ": ";
      if (message.compare(0, named.size(), named) == 0) message.erase(0, named.size());
      py::object path = py::reinterpret_steal<py::object>(
          PyUnicode_DecodeFSDefaultAndSize(e.path().data(), static_cast<Py_ssize_t>(e.path().size())));
      py::object error = py::handle(g_file_error)(e.error_number(), text(message), path);
      PyErr_SetObject(g_file_error, error.ptr());
    } catch (const InputError& e) {
      set_error(g_input_error, e.what());
    } catch (const UsageError& e) {
      set_error(g_usage_error, e.what());
    } catch (const CancelledError& e) {
      set_error(g_cancelled, e.what());
    }
  });
}

// str, bytes or os.PathLike, as the file system's bytes (os.fsencode: a
// name that is no UTF-8 too), converted while the GIL is held (bytes were
// refused with "expected a str path", 2026-11-30).
std::string path_string(py::handle path, const char* name) {
  py::object os = py::module_::import("os");
  py::object s;
  try {
    s = os.attr("fsencode")(path);
  } catch (py::error_already_set& e) {
    if (!e.matches(PyExc_TypeError)) throw;
    throw py::type_error(std::string(name) + ": expected a str, bytes or os.PathLike path");
  }
  return s.cast<std::string>();
}

// A surface to mesh from arrays, or a copy of a vdmesh.Mesh.
Mesh surface_input(py::handle points, py::handle triangles, py::handle faces, py::handle regions,
                   py::handle point_size) {
  Mesh input;
  if (py::isinstance<Mesh>(points)) {
    if (!triangles.is_none() || !faces.is_none() || !regions.is_none() || !point_size.is_none())
      throw py::type_error("mesh_surface: give either a vdmesh.Mesh or the arrays, not both");
    input = points.cast<const Mesh&>();
  } else {
    if (triangles.is_none()) throw py::type_error("mesh_surface: triangles are required with a points array");
    set_points(input, points);
    set_triangles(input, triangles);
    if (!faces.is_none()) set_triangle_faces(input, faces, "faces");
    if (!regions.is_none()) set_triangle_regions(input, regions, "regions");
    if (!point_size.is_none()) set_point_size(input, point_size);
  }
  // As `vdmesh mesh` does with a volume file: only its surface is meshed.
  input.tets.clear();
  input.tet_mid.clear();
  input.triangle_mid.clear();
  check_indices(input);
  if (input.triangles.empty()) throw InputError("no surface facets to mesh");
  return input;
}

py::tuple result_tuple(MeshResult&& result) {
  py::dict report = report_dict(result.report);
  return py::make_tuple(py::cast(std::move(result.mesh)), report);
}

py::tuple mesh_surface_py(py::object points, py::object triangles, py::object faces, py::object regions,
                          py::object point_size, const py::kwargs& kwargs) {
  RunOptions run = parse_options(kwargs, false);
  const Mesh input = surface_input(points, triangles, faces, regions, point_size);
  auto work = [&input](const MeshOptions& opt) {
    MeshResult partial;
    try {
      return mesh_surface(input, opt, &partial);
    } catch (const RecoveryError& e) {
      throw RecoveryWithReport(e, std::move(partial));
    }
  };
  return result_tuple(run_interruptible(run, work));
}

struct CadSource {
  std::string path, brep;
};

CadSource cad_source(py::handle path, py::handle brep, const char* function) {
  if (path.is_none() == brep.is_none())
    throw py::type_error(std::string(function) + ": give exactly one of path= (a STEP, IGES or BREP file) and brep= (a BREP string)");
  CadSource s;
  if (!path.is_none()) {
    s.path = path_string(path, "path");
    if (!cad::is_cad_file_name(s.path))
      throw UsageError(s.path + ": not a CAD file (.step .stp .iges .igs .brep .brp)");
  } else {
    if (!py::isinstance<py::str>(brep) && !py::isinstance<py::bytes>(brep))
      throw py::type_error("brep: expected the BREP text as str or bytes");
    s.brep = brep.cast<std::string>();
  }
  return s;
}

cad::CadModel read_cad(const CadSource& source, const std::atomic<bool>* cancel = nullptr,
                       cad::CadModel::Fuse fuse = cad::CadModel::Fuse::in_full) {
  return source.path.empty() ? cad::CadModel::from_brep_string(source.brep, "<brep>", cancel, fuse)
                             : cad::CadModel::read(source.path, cancel, fuse);
}

py::tuple mesh_cad_py(py::object path, py::object brep, const py::kwargs& kwargs) {
  RunOptions run = parse_options(kwargs, true);
  const CadSource source = cad_source(path, brep, "mesh_cad");
  const cad::CadMeshOptions base = run.cad;
  auto work = [&source, &base](const MeshOptions& opt) {
    cad::CadMeshOptions copt = base;
    copt.mesh = opt;
    if (opt.progress) opt.progress("read CAD");
    set_thread_count(opt.threads);  // the general fuse's threads too
    const cad::CadModel model = read_cad(source, opt.cancel, copt.fuse);
    throw_if_cancelled(opt.cancel);
    MeshResult partial;
    try {
      return cad::mesh_cad(model, copt, &partial);
    } catch (const RecoveryError& e) {
      throw RecoveryWithReport(e, std::move(partial));
    }
  };
  return result_tuple(run_interruptible(run, work));
}

Mesh tessellate_cad_py(py::object path, py::object brep, double size, double deflection, py::object cancel) {
  RunOptions run;
  run.token = cancel_flag(cancel);
  const CadSource source = cad_source(path, brep, "tessellate_cad");
  // As mesh_cad checks them (nan was "must not be negative", inf taken).
  if (!std::isfinite(size)) throw UsageError("option size: not a finite number");
  if (!std::isfinite(deflection)) throw UsageError("option deflection: not a finite number");
  if (!(size >= 0)) throw UsageError("option size: must not be negative");
  if (!(deflection == 0 || deflection >= cad::kSmallestDeflection))
    throw UsageError("option deflection: must be 0 (chosen per face) or at least 1e-7 (OpenCASCADE's precision)");
  // On a worker, as meshing: Ctrl-C or the token stops a tessellation of a
  // large assembly (it ran on to the end, minutes on the fuse alone).
  auto work = [&source, size, deflection](const MeshOptions& opt) {
    cad::TessellationOptions topt;
    topt.size = size;
    topt.deflection = deflection;
    topt.cancel = opt.cancel;
    const cad::CadModel model = read_cad(source, opt.cancel);
    throw_if_cancelled(opt.cancel);
    MeshResult result;
    result.mesh = model.tessellate(topt);
    return result;
  };
  return std::move(run_interruptible(run, work).mesh);
}

Mesh read_py(py::object path, const std::string& format) {
  const std::string p = path_string(path, "path");
  py::gil_scoped_release release;
  return io::read_mesh(p, format);
}

void write_py(const Mesh& mesh, py::object path, bool binary, int msh_version, const std::string& format) {
  const std::string p = path_string(path, "path");
  if (msh_version != 22 && msh_version != 41) throw UsageError("msh_version must be 22 or 41");
  check_indices(mesh);
  io::WriteOptions options;
  options.binary = binary;
  options.msh_version = msh_version;
  io::format_for(p, format);  // an unknown format before any work
  py::gil_scoped_release release;
  io::write_mesh(mesh, p, options, format);
}

py::list formats_py() {
  py::list out;
  for (const io::Format& f : io::formats())
    out.append(py::dict("name"_a = f.name, "extensions"_a = f.extensions, "volume"_a = f.holds_volume,
                        "writable"_a = static_cast<bool>(f.write)));
  return out;
}

Mesh make_mesh(py::object points, py::object triangles, py::object triangle_faces, py::object triangle_regions,
               py::object tets, py::object tet_regions, py::object point_size,
               std::map<int, std::string> region_names, std::map<int, std::string> face_names,
               py::object triangle_mid, py::object tet_mid) {
  Mesh m;
  if (!points.is_none()) set_points(m, points);
  if (!triangles.is_none()) set_triangles(m, triangles);
  if (!triangle_faces.is_none()) set_triangle_faces(m, triangle_faces);
  if (!triangle_regions.is_none()) set_triangle_regions(m, triangle_regions);
  if (!tets.is_none()) set_tets(m, tets);
  if (!tet_regions.is_none()) set_tet_regions(m, tet_regions);
  if (!point_size.is_none()) set_point_size(m, point_size);
  // After the corners, whose counts they must match.
  if (!triangle_mid.is_none()) set_triangle_mid(m, triangle_mid);
  if (!tet_mid.is_none()) set_tet_mid(m, tet_mid);
  m.region_names = std::move(region_names);
  m.face_names = std::move(face_names);
  // Given whole, a mesh is checked at once: a vertex number past the points
  // was said only by the first call that used the mesh. Without points the
  // corners wait for them (assigned next), but none is ever negative.
  if (!points.is_none()) {
    check_indices(m);
  } else {
    auto non_negative = [](const auto& elements, const char* name) {
      for (size_t i = 0; i < elements.size(); ++i)
        for (int v : elements[i].v)
          if (v < 0) throw UsageError(std::string(name) + "[" + std::to_string(i) + "] refers to vertex " + std::to_string(v));
    };
    non_negative(m.triangles, "triangles");
    non_negative(m.tets, "tets");
  }
  return m;
}

void bind_mesh(py::module_& m) {
  py::class_<Mesh>(m, "Mesh", R"(A mesh: points, tagged triangles and tetrahedra with a region.

Conventions (README, "Conventions"): region 0 is the exterior, regions are 1..N,
-1 means unknown; a triangle's normal (right-hand rule) points into its front
region; tetrahedra are positive (det(v1-v0, v2-v0, v3-v0) > 0); indices are 0-based.

Every attribute returns a new numpy array (a copy): change a mesh by assigning
whole arrays, e.g. mesh.points = mesh.points * 2. The same holds for the
region_names and face_names dicts.)")
      .def(py::init(&make_mesh), "points"_a = py::none(), "triangles"_a = py::none(), "triangle_faces"_a = py::none(),
           "triangle_regions"_a = py::none(), "tets"_a = py::none(), "tet_regions"_a = py::none(),
           "point_size"_a = py::none(), "region_names"_a = std::map<int, std::string>(),
           "face_names"_a = std::map<int, std::string>(), "triangle_mid"_a = py::none(), "tet_mid"_a = py::none(),
           "A mesh from arrays; every argument is optional (arrays as for the attributes of the same name).")
      .def_property("points", &points_array, [](Mesh& m, py::handle a) { set_points(m, a); },
                    "(N, 3) float64 coordinates")
      .def_property("point_size", &point_size_array, &set_point_size,
                    "(N,) float64 mesh size per point, or an empty array when none is given")
      .def_property("triangles", &triangles_array, [](Mesh& m, py::handle a) { set_triangles(m, a); },
                    "(F, 3) int32 vertex indices; assigning a different count keeps the tags of the first rows")
      .def_property("triangle_faces", &triangle_faces_array,
                    [](Mesh& m, py::handle a) { set_triangle_faces(m, a); },
                    "(F,) int32 topological face id per triangle (-1: none)")
      .def_property("triangle_regions", &triangle_regions_array,
                    [](Mesh& m, py::handle a) { set_triangle_regions(m, a); },
                    "(F, 2) int32 regions (front, back) per triangle; the normal points into front (-1: unknown)")
      .def_property("tets", &tets_array, &set_tets, "(T, 4) int32 vertex indices of positive tetrahedra")
      .def_property("tet_regions", &tet_regions_array, &set_tet_regions, "(T,) int32 region per tetrahedron")
      .def_property("triangle_mid", &triangle_mid_array, &set_triangle_mid,
                    "(F, 3) int32 mid-edge nodes of second-order triangles (edges 01, 12, 20), or (0, 3)")
      .def_property("tet_mid", &tet_mid_array, &set_tet_mid,
                    "(T, 6) int32 mid-edge nodes of second-order tetrahedra (edges 01, 12, 20, 03, 13, 23), or (0, 6)")
      .def_readwrite("region_names", &Mesh::region_names, "dict region id -> name (e.g. 'Solid1'); a copy")
      .def_readwrite("face_names", &Mesh::face_names, "dict face id -> name (e.g. 'Face3'); a copy")
      .def_readwrite("face_groups", &Mesh::face_groups,
                     "dict face id -> the face ids whose groups its facets belong to, for facets on several "
                     "faces (an interface of two touching CAD solids lies on a face of each); a copy")
      .def_property_readonly("second_order", &Mesh::second_order, "True when mid-edge nodes are present")
      // Pickled as its arrays and names: multiprocessing hands results back
      // so, and copy.copy / copy.deepcopy go the same way.
      .def(py::pickle(
          [](const Mesh& mesh) {
            // As write does: a state that would not load again (stale
            // mid-edge rows) is refused here, not at loads.
            check_indices(mesh);
            py::list region_points;
            for (const RegionPoint& r : mesh.region_points)
              region_points.append(py::make_tuple(r.at.x, r.at.y, r.at.z, r.region));
            return py::make_tuple(points_array(mesh), point_size_array(mesh), triangles_array(mesh),
                                  triangle_faces_array(mesh), triangle_regions_array(mesh), tets_array(mesh),
                                  tet_regions_array(mesh), triangle_mid_array(mesh), tet_mid_array(mesh),
                                  mesh.region_names, mesh.face_names, mesh.face_groups, region_points);
          },
          [](const py::tuple& t) {
            if (t.size() != 13) throw UsageError("vdmesh.Mesh: a pickled state of 13 items expected");
            Mesh mesh;
            try {
              set_points(mesh, t[0]);
              set_triangles(mesh, t[2]);
              set_triangle_faces(mesh, t[3]);
              set_triangle_regions(mesh, t[4]);
              set_tets(mesh, t[5]);
              set_tet_regions(mesh, t[6]);
              set_triangle_mid(mesh, t[7]);
              set_tet_mid(mesh, t[8]);
              set_point_size(mesh, t[1]);
              mesh.region_names = t[9].cast<std::map<int, std::string>>();
              mesh.face_names = t[10].cast<std::map<int, std::string>>();
              mesh.face_groups = t[11].cast<std::map<int, std::vector<int>>>();
              for (const py::handle r : t[12].cast<py::list>()) {
                const auto [x, y, z, region] = r.cast<std::tuple<double, double, double, int>>();
                mesh.region_points.push_back({{x, y, z}, region});
              }
            } catch (const std::exception& e) {  // a cast, or an array of the wrong kind
              throw UsageError(std::string("vdmesh.Mesh: a pickled state of another form: ") + e.what());
            }
            check_indices(mesh);
            return mesh;
          }))
      .def("__repr__", [](const Mesh& mesh) {
        return "<vdmesh.Mesh: " + std::to_string(mesh.points.size()) + " points, " +
               std::to_string(mesh.triangles.size()) + " triangles, " + std::to_string(mesh.tets.size()) +
               " tetrahedra>";
      });
}

void bind_cancel_token(py::module_& m) {
  py::class_<CancelToken>(m, "CancelToken", R"(Stops a mesh_surface / mesh_cad call from another thread.

    token = vdmesh.CancelToken()
    threading.Thread(target=lambda: vdmesh.mesh_surface(p, t, cancel=token)).start()
    token.set()   # the call raises vdmesh.Cancelled within a fraction of a second

Ctrl-C needs no token when the call runs in the main thread: it raises
KeyboardInterrupt there.)")
      .def(py::init<>())
      .def("set", [](CancelToken& t) { t.flag->store(true); }, "Ask the runs using this token to stop.")
      .def("clear", [](CancelToken& t) { t.flag->store(false); }, "Make the token usable for a new run.")
      .def("is_set", [](const CancelToken& t) { return t.flag->load(); });
}

}  // namespace
}  // namespace vd::python

PYBIND11_MODULE(vdmesh, m) {
  using namespace vd::python;
  m.doc() = R"(vdmesh: tetrahedral meshes by the variational Delaunay method of Krysl & Ortiz.

    mesh, report = vdmesh.mesh_surface(points, triangles, faces, regions, size=0.1)
    mesh, report = vdmesh.mesh_cad(path="part.step", size=2)
    mesh = vdmesh.read("in.msh"); vdmesh.write(mesh, "out.inp")

Meshes are vdmesh.Mesh objects whose attributes are numpy arrays; the report is
the dict `vdmesh mesh --report` writes as JSON. Meshing releases the GIL and
stops on Ctrl-C (KeyboardInterrupt) or through a vdmesh.CancelToken.)";
  m.attr("__version__") = VDMESH_VERSION;
  register_exceptions(m);
  bind_mesh(m);
  bind_cancel_token(m);

  const std::string options_doc = kOptionsDoc;
  m.def("mesh_surface", &mesh_surface_py, "points"_a, "triangles"_a = py::none(), "faces"_a = py::none(),
        "regions"_a = py::none(), "point_size"_a = py::none(),
        (R"(Tetrahedra of a closed triangulated surface: (mesh, report).

points: (N, 3) coordinates, or a vdmesh.Mesh (its surface is meshed; then give
    no other array).
triangles: (F, 3) vertex indices.
faces: (F,) topological face id per triangle; None: smooth patches split at
    sharp edges (sharp_angle).
regions: (F, 2) regions (front, back) per triangle, the normal pointing into
    front, 0 the exterior; None: found from the surface.
point_size: (N,) mesh size per point, or None.

Returns the output mesh (surface with face ids and regions, tetrahedra with
their region) and the report dict. Raises vdmesh.InputError for invalid input,
vdmesh.RecoveryError when facets stay non-Delaunay within the guards,
ValueError/TypeError for bad arguments or options.

)" + options_doc).c_str());
  m.def("mesh_cad", &mesh_cad_py, "path"_a = py::none(), "brep"_a = py::none(),
        (R"(Tetrahedra of a CAD part or assembly: (mesh, report).

path: a .step/.stp, .iges/.igs or .brep/.brp file; or
brep: the text of a BREP (what Part.Shape.exportBrepToString() gives in FreeCAD).

Touching solids are fused first, so that shared faces become interfaces.
Region i is Solid<i> and face j is Face<j> (1-based, FreeCAD's numbering);
mesh.region_names and mesh.face_names hold these names. report['cad'] gives
OpenCASCADE's volume per solid and area per face beside the mesh's.

)" + options_doc).c_str());
  m.def("tessellate_cad", &tessellate_cad_py, "path"_a = py::none(), "brep"_a = py::none(), "size"_a = 0.0,
        "deflection"_a = 0.0, "cancel"_a = py::none(),
        "The tagged surface mesh_cad starts from (face ids, solid regions), as `vdmesh convert part.step out.stl` "
        "writes it; size 0: chosen from the part. Stops on Ctrl-C or through cancel (a vdmesh.CancelToken).");
  m.def("read", &read_py, "path"_a, "format"_a = "",
        "Read a mesh file of any format vdmesh knows (see formats()); format: a format name when the extension "
        "is ambiguous. Raises vdmesh.InputError naming the file and line for malformed content.");
  m.def("write", &write_py, "mesh"_a, "path"_a, "binary"_a = false, "msh_version"_a = 41, "format"_a = "",
        "Write a mesh; the format follows the extension (or format=). binary: the binary variant where there is "
        "one; msh_version: 22 or 41 for Gmsh files.");
  m.def("formats", &formats_py,
        "The formats read() and write() know: dicts with name, extensions, volume (can hold tetrahedra) and "
        "writable.");
}
