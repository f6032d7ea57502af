#include "python/mesh_arrays.h"

#include <algorithm>
#include <climits>
#include <cmath>
#include <string>

#include "mesh/error.h"

namespace vd::python {
namespace {

std::string shape_text(const py::array& a) {
  std::string s = "(";
  for (py::ssize_t i = 0; i < a.ndim(); ++i) s += (i ? ", " : "") + std::to_string(a.shape(i));
  return s + (a.ndim() == 1 ? ",)" : ")");
}

// An (n, cols) array, or (n,) when cols == 0; `what` names the columns in
// the error message ("(N, 3)").
void check_shape(const py::array& a, int cols, const char* name, const char* what) {
  const bool ok = cols == 0 ? a.ndim() == 1 : (a.ndim() == 2 && a.shape(1) == cols);
  // An empty list converts to shape (0,): accept it as "no rows".
  if (ok || (a.size() == 0 && a.ndim() == 1)) return;
  throw UsageError(std::string(name) + ": expected an array of shape " + what + ", got shape " + shape_text(a));
}

py::array as_array(py::handle obj, const char* name) {
  py::array a = py::array::ensure(obj);
  if (!a) throw py::type_error(std::string(name) + ": expected an array-like of numbers");
  return a;
}

// Rows of integers (vertex indices or tags). Floats are refused rather than
// truncated: 2.7 as a vertex index is a bug in the caller.
std::vector<long long> read_integers(py::handle obj, int cols, const char* name, const char* what) {
  const py::array any = as_array(obj, name);
  check_shape(any, cols, name, what);
  const char kind = any.dtype().kind();
  if (any.size() > 0 && kind != 'i' && kind != 'u')
    throw py::type_error(std::string(name) + ": expected integers, got dtype " +
                         py::str(any.dtype()).cast<std::string>());
  // Unsigned 64-bit values past 2^63 would wrap to negatives in the cast
  // below (2^64 - 1 was taken as region -1, "unknown").
  if (kind == 'u' && any.itemsize() == 8) {
    const auto u = py::array_t<unsigned long long, py::array::c_style | py::array::forcecast>::ensure(any);
    for (py::ssize_t i = 0; i < u.size(); ++i)
      if (u.data()[i] > static_cast<unsigned long long>(INT_MAX))
        throw UsageError(std::string(name) + ": value " + std::to_string(u.data()[i]) + " out of range");
  }
  const auto a = py::array_t<long long, py::array::c_style | py::array::forcecast>::ensure(any);
  std::vector<long long> out(a.data(), a.data() + a.size());
  for (long long x : out)
    if (x < INT_MIN || x > INT_MAX) throw UsageError(std::string(name) + ": value " + std::to_string(x) + " out of range");
  return out;
}

std::vector<double> read_numbers(py::handle obj, int cols, const char* name, const char* what) {
  const py::array any = as_array(obj, name);
  check_shape(any, cols, name, what);
  const char kind = any.dtype().kind();
  if (any.size() > 0 && kind != 'f' && kind != 'i' && kind != 'u')
    throw py::type_error(std::string(name) + ": expected numbers, got dtype " + py::str(any.dtype()).cast<std::string>());
  const auto a = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(any);
  std::vector<double> out(a.data(), a.data() + a.size());
  for (size_t i = 0; i < out.size(); ++i)
    if (!std::isfinite(out[i]))
      throw UsageError(std::string(name) + ": row " + std::to_string(cols ? i / cols : i) + " is not finite");
  return out;
}

template <class T>
py::array_t<T> make(py::ssize_t rows, py::ssize_t cols) {
  return cols == 0 ? py::array_t<T>(std::vector<py::ssize_t>{rows}) : py::array_t<T>(std::vector<py::ssize_t>{rows, cols});
}

// Copies `rows` items, each giving `cols` values through `get(item, j)`.
template <class T, class Items, class Get>
py::array_t<T> table(const Items& items, py::ssize_t cols, Get get) {
  auto a = make<T>(static_cast<py::ssize_t>(items.size()), cols);
  T* out = a.mutable_data();
  const py::ssize_t width = cols == 0 ? 1 : cols;
  for (size_t i = 0; i < items.size(); ++i)
    for (py::ssize_t j = 0; j < width; ++j) out[i * width + j] = get(items[i], static_cast<int>(j));
  return a;
}

void require_count(size_t got, size_t want, const char* name, const char* of) {
  if (got != want)
    throw UsageError(std::string(name) + ": " + std::to_string(got) + " rows for " + std::to_string(want) + " " + of);
}

}  // namespace

py::array_t<double> points_array(const Mesh& m) {
  return table<double>(m.points, 3, [](const Vec3& p, int j) { return p[j]; });
}
py::array_t<double> point_size_array(const Mesh& m) {
  return table<double>(m.point_size, 0, [](double h, int) { return h; });
}
py::array_t<int> triangles_array(const Mesh& m) {
  return table<int>(m.triangles, 3, [](const Triangle& t, int j) { return t.v[j]; });
}
py::array_t<int> triangle_faces_array(const Mesh& m) {
  return table<int>(m.triangles, 0, [](const Triangle& t, int) { return t.face; });
}
py::array_t<int> triangle_regions_array(const Mesh& m) {
  return table<int>(m.triangles, 2, [](const Triangle& t, int j) { return j == 0 ? t.front : t.back; });
}
py::array_t<int> tets_array(const Mesh& m) {
  return table<int>(m.tets, 4, [](const Tetrahedron& t, int j) { return t.v[j]; });
}
py::array_t<int> tet_regions_array(const Mesh& m) {
  return table<int>(m.tets, 0, [](const Tetrahedron& t, int) { return t.region; });
}
py::array_t<int> triangle_mid_array(const Mesh& m) {
  return table<int>(m.triangle_mid, 3, [](const TriMidNodes& t, int j) { return t[j]; });
}
py::array_t<int> tet_mid_array(const Mesh& m) {
  return table<int>(m.tet_mid, 6, [](const TetMidNodes& t, int j) { return t[j]; });
}

void set_points(Mesh& m, py::handle a, const char* name) {
  const auto v = read_numbers(a, 3, name, "(N, 3)");
  m.points.resize(v.size() / 3);
  for (size_t i = 0; i < m.points.size(); ++i) m.points[i] = {v[3 * i], v[3 * i + 1], v[3 * i + 2]};
}

void set_point_size(Mesh& m, py::handle a) {
  auto v = read_numbers(a, 0, "point_size", "(N,)");
  if (!v.empty()) require_count(v.size(), m.points.size(), "point_size", "points");
  m.point_size = std::move(v);
}

void set_triangles(Mesh& m, py::handle a, const char* name) {
  const auto v = read_integers(a, 3, name, "(F, 3)");
  m.triangles.resize(v.size() / 3);
  for (size_t i = 0; i < m.triangles.size(); ++i)
    for (int j = 0; j < 3; ++j) m.triangles[i].v[j] = static_cast<int>(v[3 * i + j]);
}

void set_triangle_faces(Mesh& m, py::handle a, const char* name) {
  const auto v = read_integers(a, 0, name, "(F,)");
  require_count(v.size(), m.triangles.size(), name, "triangles");
  for (size_t i = 0; i < v.size(); ++i) m.triangles[i].face = static_cast<int>(v[i]);
}

void set_triangle_regions(Mesh& m, py::handle a, const char* name) {
  const auto v = read_integers(a, 2, name, "(F, 2) (front, back)");
  require_count(v.size() / 2, m.triangles.size(), name, "triangles");
  for (size_t i = 0; i < m.triangles.size(); ++i) {
    m.triangles[i].front = static_cast<int>(v[2 * i]);
    m.triangles[i].back = static_cast<int>(v[2 * i + 1]);
  }
}

void set_tets(Mesh& m, py::handle a) {
  const auto v = read_integers(a, 4, "tets", "(T, 4)");
  m.tets.resize(v.size() / 4);
  for (size_t i = 0; i < m.tets.size(); ++i)
    for (int j = 0; j < 4; ++j) m.tets[i].v[j] = static_cast<int>(v[4 * i + j]);
}

void set_tet_regions(Mesh& m, py::handle a) {
  const auto v = read_integers(a, 0, "tet_regions", "(T,)");
  require_count(v.size(), m.tets.size(), "tet_regions", "tetrahedra");
  for (size_t i = 0; i < v.size(); ++i) m.tets[i].region = static_cast<int>(v[i]);
}

void set_triangle_mid(Mesh& m, py::handle a) {
  const auto v = read_integers(a, 3, "triangle_mid", "(F, 3)");
  if (!v.empty()) require_count(v.size() / 3, m.triangles.size(), "triangle_mid", "triangles");
  m.triangle_mid.resize(v.size() / 3);
  for (size_t i = 0; i < m.triangle_mid.size(); ++i)
    for (int j = 0; j < 3; ++j) m.triangle_mid[i][j] = static_cast<int>(v[3 * i + j]);
}

void set_tet_mid(Mesh& m, py::handle a) {
  const auto v = read_integers(a, 6, "tet_mid", "(T, 6)");
  if (!v.empty()) require_count(v.size() / 6, m.tets.size(), "tet_mid", "tetrahedra");
  m.tet_mid.resize(v.size() / 6);
  for (size_t i = 0; i < m.tet_mid.size(); ++i)
    for (int j = 0; j < 6; ++j) m.tet_mid[i][j] = static_cast<int>(v[6 * i + j]);
}

void check_indices(const Mesh& m) {
  const long n = static_cast<long>(m.points.size());
  auto check = [&](const auto& rows, const char* name) {
    for (size_t i = 0; i < rows.size(); ++i)
      for (int v : rows[i])
        if (v < 0 || v >= n)
          throw UsageError(std::string(name) + "[" + std::to_string(i) + "] refers to vertex " + std::to_string(v) +
                                ", but there are " + std::to_string(n) + " points");
  };
  std::vector<std::array<int, 3>> tri;
  for (const Triangle& t : m.triangles) tri.push_back(t.v);
  std::vector<std::array<int, 4>> tet;
  for (const Tetrahedron& t : m.tets) tet.push_back(t.v);
  check(tri, "triangles");
  check(tet, "tets");
  // Mid-edge nodes are rows beside the corners: new corners (a region
  // picked out of a second-order mesh) left them stale, and the writers
  // read past their end (node ids of -4e8 in the file).
  auto same_rows = [](size_t mids, size_t corners, const char* name, const char* of) {
    if (mids != 0 && mids != corners)
      throw UsageError(std::string(name) + " has " + std::to_string(mids) + " rows for " + std::to_string(corners) +
                            " " + of + ": give " + name + " again after " + of + " (an empty array for first order)");
  };
  same_rows(m.triangle_mid.size(), m.triangles.size(), "triangle_mid", "triangles");
  // Writers put a facet into each group listed: an empty list dropped its
  // facets from the Abaqus deck and MSH 2.2, a repeated one wrote them twice.
  for (const auto& [face, groups] : m.face_groups) {
    std::vector<int> sorted = groups;
    std::sort(sorted.begin(), sorted.end());
    if (face < 1 || groups.empty() || sorted.front() < 1 ||
        std::adjacent_find(sorted.begin(), sorted.end()) != sorted.end())
      throw UsageError("face_groups[" + std::to_string(face) +
                            "]: keys and their lists must be face ids of 1 or more, each list not empty and "
                            "without repeats");
  }
  same_rows(m.tet_mid.size(), m.tets.size(), "tet_mid", "tets");
  check(m.triangle_mid, "triangle_mid");
  check(m.tet_mid, "tet_mid");
  if (!m.point_size.empty() && m.point_size.size() != m.points.size())
    throw UsageError("point_size: " + std::to_string(m.point_size.size()) + " values for " + std::to_string(n) +
                          " points");
}

}  // namespace vd::python
