// vd::Mesh to and from numpy arrays for the Python module. Every array handed
// to Python is a fresh copy (C order; float64 coordinates, int32 indices and
// tags): Python code can keep or change it without touching the mesh.
#pragma once

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include "mesh/mesh.h"

namespace vd::python {

namespace py = pybind11;

// Mesh parts as arrays.
py::array_t<double> points_array(const Mesh& m);                 // (N, 3)
py::array_t<double> point_size_array(const Mesh& m);             // (N,) or (0,)
py::array_t<int> triangles_array(const Mesh& m);                 // (F, 3)
py::array_t<int> triangle_faces_array(const Mesh& m);            // (F,)
py::array_t<int> triangle_regions_array(const Mesh& m);          // (F, 2): front, back
py::array_t<int> tets_array(const Mesh& m);                      // (T, 4)
py::array_t<int> tet_regions_array(const Mesh& m);               // (T,)
py::array_t<int> triangle_mid_array(const Mesh& m);              // (F, 3) or (0, 3)
py::array_t<int> tet_mid_array(const Mesh& m);                   // (T, 6) or (0, 6)

// Setters: `name` appears in the ValueError/TypeError raised for a wrong
// shape, a non-integer index array or a non-finite coordinate.
void set_points(Mesh& m, py::handle a, const char* name = "points");
void set_point_size(Mesh& m, py::handle a);
// Keeps the tags of the first triangles when the count changes; new ones are untagged.
void set_triangles(Mesh& m, py::handle a, const char* name = "triangles");
void set_triangle_faces(Mesh& m, py::handle a, const char* name = "triangle_faces");
void set_triangle_regions(Mesh& m, py::handle a, const char* name = "triangle_regions");
void set_tets(Mesh& m, py::handle a);
void set_tet_regions(Mesh& m, py::handle a);
void set_triangle_mid(Mesh& m, py::handle a);
void set_tet_mid(Mesh& m, py::handle a);

// Every vertex index refers to an existing point: a ValueError naming the
// first bad row otherwise (the core trusts its indices).
void check_indices(const Mesh& m);

}  // namespace vd::python
