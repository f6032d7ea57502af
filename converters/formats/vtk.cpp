// Legacy VTK (.vtk), ASCII and binary (big-endian): DATASET UNSTRUCTURED_GRID,
// and DATASET POLYDATA read as a surface (its polygons triangulated, its
// triangle strips cut into triangles, its vertices and lines skipped).
// Writes the classic CELLS layout (version 3.0, which Gmsh and VTK 9 read);
// reads it and the 5.1 OFFSETS/CONNECTIVITY layout. Cell data: "region",
// "face", "front", "back" (int).
#include <algorithm>
#include <cmath>
#include <map>

#include "formats.h"
#include "io_util.h"
#include "polygon_triangulation.h"
#include "vtk_common.h"

namespace vd::io {
namespace {

using detail::Cursor;
using detail::FileBytes;

// A binary array's value type, looked up once per array.
using Binary = detail::ValueType;

Binary binary_type(std::string_view type) {
  const std::string t = detail::to_lower(type);
  if (t == "char") return Binary::Int8;
  if (t == "unsigned_char") return Binary::UInt8;
  if (t == "short") return Binary::Int16;
  if (t == "unsigned_short") return Binary::UInt16;
  if (t == "int" || t == "vtktypeint32") return Binary::Int32;
  if (t == "unsigned_int" || t == "vtktypeuint32") return Binary::UInt32;
  if (t == "long" || t == "vtktypeint64" || t == "vtkidtype") return Binary::Int64;
  if (t == "unsigned_long" || t == "vtktypeuint64") return Binary::UInt64;
  if (t == "float") return Binary::Float32;
  if (t == "double") return Binary::Float64;
  return Binary::Unknown;
}

// Reads the file in one pass straight into the mesh: the connectivity waits
// (4 bytes a node) until CELL_TYPES says which cells are tetrahedra and
// triangles, and cell data goes into them as it is read. Holding every array
// as int64 and double before assembling peaked at 7 times the mesh.
class LegacyReader {
 public:
  LegacyReader(const FileBytes& data, const std::string& path) : in_(data, path) {}
  Mesh read();

 private:
  // Calls store(i, value) for `count` values of `type`.
  template <class Store>
  void values(uint64_t count, std::string_view type, Store store);
  void skip_values(uint64_t count, std::string_view type) {
    if (detail::iequals(type, "string") || detail::iequals(type, "utf8_string")) return skip_strings(count);
    values(count, type, [](uint64_t, double) {});
  }
  void skip_strings(uint64_t count);
  int64_t cell_index(Binary type);
  void read_points();
  // CELLS, or a POLYDATA section (`section`: its keyword, lower case), whose
  // cells are added to those of the sections before it.
  void read_cells(const std::string& section = "cells");
  // The triangles of a POLYDATA polygon or strip (cell `i`, `k` nodes at `v`).
  void add_polydata_triangles(size_t i, int type, const int32_t* v, int64_t k);
  // Cell data value `v` of cell `i` onto the triangles or tetrahedron it became.
  void put(detail::VtkCellDataSink& sink, uint64_t i, double v);
  void read_cell_types();
  void build_elements();
  detail::VtkCellRoles roles_of(const std::string& name);
  // A cell data array: its values go to the tetrahedra or triangles.
  void cell_array(const std::string& name, uint64_t n, std::string_view type);
  // `dataset`: the field data of the data set itself, before any section.
  void attributes(uint64_t n, bool cell_data, bool dataset = false);
  // The region and face names of kVtkNamesArray (other types skipped).
  void names(uint64_t count, std::string_view type);
  void skip_metadata();
  void expect_word(std::string_view w);

  Cursor in_;
  bool binary_ = false;
  Mesh m_;
  std::vector<int32_t> conn_;
  std::vector<uint8_t> sizes_;             // nodes per cell; 255: look in large_
  std::map<uint64_t, int64_t> large_;      // cells of 255 nodes or more
  std::vector<uint8_t> types_;             // per cell; 255 for types beyond 254
  bool have_cells_ = false, have_types_ = false, built_ = false;
  bool polydata_ = false;
  bool data_seen_ = false;  // a CELL_DATA or POINT_DATA section was read
  std::vector<uint32_t> triangles_of_;  // POLYDATA: per cell, the triangles it became
  // Cell data read before CELL_TYPES, applied once the elements exist.
  std::vector<std::pair<detail::VtkCellRoles, std::vector<double>>> pending_;
  // Which array set the region / face so far: a lower rank wins.
  int region_rank_ = 99, face_rank_ = 99;
};

void LegacyReader::expect_word(std::string_view w) {
  const std::string_view t = in_.token(std::string(w).c_str());
  if (!detail::iequals(t, w)) in_.fail("expected " + std::string(w) + ", found '" + std::string(t.substr(0, 40)) + "'");
}

// VTK's string arrays (a FIELD array of names, say; refused as "expected a
// number" until 2026-11-30): in ASCII one string a line, in binary each
// string after its length, whose first byte's top two bits say how many
// bytes hold it (11: that byte, 10: two, 01: four, 00: eight, big-endian).
void LegacyReader::skip_strings(uint64_t count) {
  if (!binary_) {
    in_.skip_line();  // the array's header line
    for (uint64_t i = 0; i < count; ++i) {
      if (in_.at_end()) in_.fail("file ends inside a string array");
      in_.skip_line();
    }
    return;
  }
  in_.skip_newline();
  for (uint64_t i = 0; i < count; ++i) {
    const uint8_t first = in_.get<uint8_t>("a string length");
    const int more = (first >> 6) == 3 ? 0 : (first >> 6) == 2 ? 1 : (first >> 6) == 1 ? 3 : 7;
    uint64_t length = first & 0x3f;
    for (int k = 0; k < more; ++k) length = (length << 8) | in_.get<uint8_t>("a string length");
    in_.skip_bytes(length, "a string");
  }
}

template <class Store>
void LegacyReader::values(uint64_t count, std::string_view type, Store store) {
  if (!binary_) {
    for (uint64_t i = 0; i < count; ++i) {
      const std::string_view t = in_.token("a data value");
      double v;
      if (!Cursor::parse_real(t, v)) {
        // Data arrays may hold nan; coordinates are checked by the caller.
        if (detail::iequals(t, "nan") || detail::iequals(t, "-nan")) v = NAN;
        else in_.fail("expected a number, found '" + std::string(t.substr(0, 40)) + "'");
      }
      store(i, v);
    }
    return;
  }
  const Binary bt = binary_type(type);
  const size_t size = detail::value_size(bt);
  if (size == 0) in_.fail("unsupported binary data type '" + std::string(type.substr(0, 40)) + "'");
  in_.skip_newline();
  if (count > in_.remaining() / size) in_.fail("file ends inside a data array of " + std::to_string(count) + " values");
  for (uint64_t i = 0; i < count; ++i) {
    double v;
    switch (bt) {
      case Binary::Int8: v = in_.get<int8_t>("a value"); break;
      case Binary::UInt8: v = in_.get<uint8_t>("a value"); break;
      case Binary::Int16: v = in_.get_be<int16_t>("a value"); break;
      case Binary::UInt16: v = in_.get_be<uint16_t>("a value"); break;
      case Binary::Int32: v = in_.get_be<int32_t>("a value"); break;
      case Binary::UInt32: v = in_.get_be<uint32_t>("a value"); break;
      case Binary::Int64: v = static_cast<double>(in_.get_be<int64_t>("a value")); break;
      case Binary::UInt64: v = static_cast<double>(in_.get_be<uint64_t>("a value")); break;
      case Binary::Float32: v = in_.get_be<float>("a value"); break;
      default: v = in_.get_be<double>("a value"); break;
    }
    store(i, v);
  }
}

int64_t LegacyReader::cell_index(Binary type) {
  if (!binary_) return in_.integer("a cell index");
  return type == Binary::Int32 ? in_.get_be<int32_t>("a cell index") : in_.get_be<int64_t>("a cell index");
}

void LegacyReader::read_points() {
  if (!m_.points.empty()) in_.fail("a second POINTS section");
  const uint64_t n = in_.count("the number of points", in_.remaining());
  const std::string type(in_.token("the point type"));
  m_.points.resize(static_cast<size_t>(n));
  values(3 * n, type, [&](uint64_t i, double v) {
    if (!std::isfinite(v)) in_.fail("point " + std::to_string(i / 3) + " has a coordinate that is not a finite number");
    m_.points[i / 3][static_cast<int>(i % 3)] = v;
  });
}

void LegacyReader::read_cells(const std::string& section) {
  const std::string keyword = detail::to_upper(section);
  if (built_ || data_seen_) in_.fail(keyword + " after the point or cell data");
  if (have_cells_ && !polydata_) in_.fail("a second CELLS section");
  if (polydata_ && m_.points.empty()) in_.fail(keyword + " before POINTS");
  // A POLYDATA section's cells follow those of the sections before it.
  const size_t base = sizes_.size();
  const uint64_t a = in_.count("the number of cells", in_.remaining());
  const uint64_t b = in_.count("the cell list size", in_.remaining());
  const int64_t np = static_cast<int64_t>(m_.points.size());
  // Checked here, while the line is known (points come first in VTK).
  auto node = [&](Binary type) {
    const int64_t v = cell_index(type);
    if (v < 0 || v >= np)
      in_.fail("a cell refers to point " + std::to_string(v) + ", which does not exist (" + std::to_string(np) +
               " points)");
    return static_cast<int32_t>(v);
  };
  auto set_size = [&](uint64_t i, int64_t k) {
    sizes_[base + i] = static_cast<uint8_t>(k < 255 ? k : 255);
    if (k >= 255) large_[base + i] = k;
  };
  sizes_.resize(base + static_cast<size_t>(a), 0);  // a <= the bytes left
  // Peek at the next token; at_end() first so seeking back crosses no line.
  if (in_.at_end()) in_.fail("unexpected end of file in CELLS");
  const size_t mark = in_.pos();
  const std::string_view next = in_.token("the cells");
  if (detail::iequals(next, "OFFSETS")) {
    // Version 5: a offsets (the first is 0), then b connectivity entries.
    const std::string otype(in_.token("the offset type"));
    const Binary ot = binary_type(otype);
    if (binary_ && ot != Binary::Int32 && ot != Binary::Int64) in_.fail("cell offsets must be 4 or 8 byte integers");
    if (binary_) in_.skip_newline();
    if (a == 0) in_.fail("offsets must start with 0");
    if (binary_ && a > in_.remaining() / 4) in_.fail("file ends inside the cells");
    int64_t previous = cell_index(ot);
    if (previous != 0) in_.fail("offsets must start with 0");
    sizes_.resize(base + static_cast<size_t>(a - 1));
    for (uint64_t i = 0; i + 1 < a; ++i) {
      const int64_t end = cell_index(ot);
      if (end < previous || static_cast<uint64_t>(end) > b) in_.fail("cell " + std::to_string(i) + " has bad offsets");
      set_size(i, end - previous);
      previous = end;
    }
    if (static_cast<uint64_t>(previous) != b) in_.fail("the offsets end at " + std::to_string(previous) +
                                                       ", the connectivity has " + std::to_string(b) + " entries");
    expect_word("CONNECTIVITY");
    const std::string ctype(in_.token("the connectivity type"));
    const Binary ct = binary_type(ctype);
    if (binary_ && ct != Binary::Int32 && ct != Binary::Int64) in_.fail("cell indices must be 4 or 8 byte integers");
    if (binary_) in_.skip_newline();
    if (binary_ && b > in_.remaining() / 4) in_.fail("file ends inside the cells");
    conn_.reserve(conn_.size() + static_cast<size_t>(b));
    for (uint64_t j = 0; j < b; ++j) conn_.push_back(node(ct));
  } else {
    in_.seek(mark);
    if (binary_) in_.skip_newline();
    if (binary_ && b > in_.remaining() / 4) in_.fail("file ends inside the cells");
    conn_.reserve(conn_.size() + detail::capped(b >= a ? b - a : 0, in_.remaining(), binary_ ? 4 : 2));
    uint64_t read = 0;
    for (uint64_t i = 0; i < a; ++i) {
      if (read >= b) in_.fail("the cell list is shorter than its " + std::to_string(a) + " cells");
      const int64_t k = cell_index(Binary::Int32);
      ++read;
      if (k < 0 || static_cast<uint64_t>(k) > b - read) in_.fail("cell " + std::to_string(i) + " has a bad size");
      set_size(i, k);
      for (int64_t j = 0; j < k; ++j) conn_.push_back(node(Binary::Int32));
      read += static_cast<uint64_t>(k);
    }
    if (read != b) in_.fail("the cell list size does not match its cells");
  }
  have_cells_ = true;
  if (!polydata_) return;
  // VTK's cell types for what POLYDATA's sections hold: poly-vertices and
  // polylines (skipped), triangles, polygons, triangle strips.
  for (size_t i = base; i < sizes_.size(); ++i) {
    const int64_t k = sizes_[i] == 255 ? large_[i] : sizes_[i];
    const uint8_t type = section == "vertices" ? 2
                         : section == "lines"  ? 4
                         : section == "triangle_strips" ? 6
                         : k == 3               ? detail::kVtkTriangle
                                                : 7;
    types_.push_back(type);
  }
  have_types_ = true;
}

void LegacyReader::read_cell_types() {
  if (have_types_) in_.fail("a second CELL_TYPES section");
  const uint64_t n = in_.count("the number of cell types", in_.remaining());
  if (binary_) in_.skip_newline();
  if (binary_ && n > in_.remaining() / 4) in_.fail("file ends inside the cell types");
  types_.resize(static_cast<size_t>(std::min<uint64_t>(n, in_.remaining())));
  for (uint64_t i = 0; i < n; ++i) {
    const int64_t t = cell_index(Binary::Int32);
    types_[i] = static_cast<uint8_t>(t >= 0 && t < 255 ? t : 255);
  }
  have_types_ = true;
}

// The tetrahedra and triangles from the connectivity, once both cells and
// types are known; points and lines are skipped, other cells refused.
void LegacyReader::build_elements() {
  if (built_ || !have_cells_ || !have_types_) return;
  if (types_.size() != sizes_.size())
    in_.fail("CELL_TYPES has " + std::to_string(types_.size()) + " entries for " + std::to_string(sizes_.size()) +
             " cells");
  const detail::VtkElementCounts counts(types_);
  if (counts.mixed_order()) in_.fail("first- and second-order cells of one kind are mixed");
  // POLYDATA's polygons and strips become triangles (add_polydata_triangles).
  if (counts.first_lost >= 0 && !polydata_) in_.fail(counts.lost_text(types_));
  if (polydata_) triangles_of_.assign(types_.size(), 0);
  m_.tets.reserve(counts.tets);
  m_.tet_mid.reserve(counts.tets10);
  m_.triangles.reserve(counts.tris);
  m_.triangle_mid.reserve(counts.tris6);
  size_t at = 0;
  for (size_t i = 0; i < types_.size(); ++i) {
    const int64_t k = sizes_[i] == 255 ? large_[i] : sizes_[i];
    const int type = types_[i];
    const int want = detail::vtk_element_nodes(type);
    if (want && k != want)
      in_.fail("cell " + std::to_string(i) + " of type " + std::to_string(type) + " has " + std::to_string(k) +
               " nodes, not " + std::to_string(want));
    const int32_t* v = conn_.data() + at;
    if (detail::vtk_is_tet(type)) {
      Tetrahedron t;
      t.v = {v[0], v[1], v[2], v[3]};
      m_.tets.push_back(t);
      if (want == 10) m_.tet_mid.push_back({v[4], v[5], v[6], v[7], v[8], v[9]});
    } else if (detail::vtk_is_triangle(type)) {
      Triangle t;
      t.v = {v[0], v[1], v[2]};
      m_.triangles.push_back(t);
      if (want == 6) m_.triangle_mid.push_back({v[3], v[4], v[5]});
      if (polydata_) triangles_of_[i] = 1;
    } else if (polydata_ && (type == 6 || type == 7)) {
      add_polydata_triangles(i, type, v, k);
    }
    at += static_cast<size_t>(k);
  }
  conn_ = {};
  sizes_ = {};
  large_.clear();
  built_ = true;
  for (const auto& [roles, data] : pending_) {
    detail::VtkCellDataSink sink(m_, roles);
    for (size_t i = 0; i < data.size(); ++i) put(sink, i, data[i]);
  }
  pending_.clear();
}

void LegacyReader::add_polydata_triangles(size_t i, int type, const int32_t* v, int64_t k) {
  const size_t before = m_.triangles.size();
  if (type == 6) {
    for (const auto& corners : detail::strip_triangles(v, static_cast<size_t>(std::max<int64_t>(k, 0)))) {
      Triangle t;
      t.v = corners;
      m_.triangles.push_back(t);
    }
  } else {
    if (k < 3) in_.fail("polygon " + std::to_string(i) + " has " + std::to_string(k) + " nodes");
    const std::vector<int> polygon(v, v + k);
    for (const auto& corners : detail::triangulate_polygon(m_.points, polygon)) {
      Triangle t;
      t.v = corners;
      m_.triangles.push_back(t);
    }
  }
  triangles_of_[i] = static_cast<uint32_t>(m_.triangles.size() - before);
}

void LegacyReader::put(detail::VtkCellDataSink& sink, uint64_t i, double v) {
  if (!polydata_) return sink.put(types_[i], v);
  if (!detail::vtk_is_triangle(types_[i]) && types_[i] != 6 && types_[i] != 7) return;
  for (uint32_t r = 0; r < triangles_of_[i]; ++r) sink.put(detail::kVtkTriangle, v);
}

detail::VtkCellRoles LegacyReader::roles_of(const std::string& name) {
  // "region" and "face" are vdmesh's own; a tag array of another program
  // stands in for both when they are missing.
  int tag_rank = 99;
  for (size_t r = 0; r < std::size(detail::kVtkTagArrays); ++r)
    if (name == detail::kVtkTagArrays[r]) tag_rank = 1 + static_cast<int>(r);
  const int region = name == "region" ? 0 : tag_rank, face = name == "face" ? 0 : tag_rank;
  detail::VtkCellRoles r;
  if (region < region_rank_) r.region = true, region_rank_ = region;
  if (face < face_rank_) r.face = true, face_rank_ = face;
  r.front = name == "front";
  r.back = name == "back";
  return r;
}

void LegacyReader::cell_array(const std::string& name, uint64_t n, std::string_view type) {
  const uint64_t cells = have_types_ ? types_.size() : sizes_.size();
  const detail::VtkCellRoles roles =
      (have_cells_ || have_types_) && n == cells ? roles_of(name) : detail::VtkCellRoles{};
  if (!roles.any()) return skip_values(n, type);
  if (built_) {
    detail::VtkCellDataSink sink(m_, roles);
    values(n, type, [&](uint64_t i, double v) { put(sink, i, v); });
    return;
  }
  std::vector<double> data(static_cast<size_t>(n));
  values(n, type, [&](uint64_t i, double v) { data[i] = v; });
  pending_.emplace_back(roles, std::move(data));
}

// After the METADATA keyword: lines of information up to an empty line.
void LegacyReader::skip_metadata() {
  in_.skip_line();
  while (in_.pos() < in_.data().size() && !in_.rest_of_line().empty()) {
  }
}

void LegacyReader::names(uint64_t count, std::string_view type) {
  if (!detail::iequals(type, "unsigned_char")) return skip_values(count, type);
  std::string text(count, '\0');
  values(count, type, [&](uint64_t i, double v) {
    if (!(v >= 0 && v <= 255)) in_.fail("a byte of " + std::string(detail::kVtkNamesArray) + " out of 0..255");
    text[i] = static_cast<char>(static_cast<unsigned char>(v));
  });
  detail::read_vtk_names_text(text, m_);
}

void LegacyReader::attributes(uint64_t n, bool cell_data, bool dataset) {
  // Runs until the next CELL_DATA / POINT_DATA or the end of the file.
  for (;;) {
    if (in_.at_end()) return;
    const size_t mark = in_.pos();
    const std::string keyword = detail::to_lower(in_.token("a data keyword"));
    if (keyword == "scalars") {
      const std::string name(in_.token("a scalars name"));
      const std::string type(in_.token("a scalars type"));
      uint64_t ncomp = 1;
      if (in_.line_has_more()) ncomp = in_.count("the number of components", 4);
      if (ncomp == 0) in_.fail("zero components");
      std::string_view look = in_.token("LOOKUP_TABLE");
      if (!detail::iequals(look, "LOOKUP_TABLE")) in_.fail("expected LOOKUP_TABLE");
      in_.token("a lookup table name");
      if (cell_data && ncomp == 1) cell_array(name, n, type);
      else skip_values(n * ncomp, type);
      continue;
    }
    if (keyword == "field") {
      in_.token("a field name");
      const uint64_t arrays = in_.count("the number of arrays", 1 << 20);
      for (uint64_t a = 0; a < arrays; ++a) {
        std::string name(in_.token("an array name"));
        // VTK 8 and later follow an array with its METADATA (field arrays
        // of vtkUnstructuredGridWriter's files included).
        if (detail::iequals(name, "METADATA")) {
          skip_metadata();
          name = in_.token("an array name");
        }
        const uint64_t ncomp = in_.count("the number of components", 1 << 20);
        const uint64_t tuples = in_.count("the number of tuples");
        const std::string type(in_.token("an array type"));
        if (ncomp == 0 || tuples > in_.remaining()) in_.fail("bad field array size");
        if (cell_data && ncomp == 1 && tuples == n) cell_array(name, n, type);
        else if (dataset && ncomp == 1 && name == detail::kVtkNamesArray) names(tuples, type);
        else skip_values(ncomp * tuples, type);
      }
      continue;
    }
    if (keyword == "vectors" || keyword == "normals" || keyword == "tensors") {
      in_.token("a name");
      const std::string type(in_.token("a type"));
      skip_values(n * (keyword == "tensors" ? 9 : 3), type);
      continue;
    }
    if (keyword == "texture_coordinates") {
      in_.token("a name");
      const uint64_t dim = in_.count("the dimension", 3);
      const std::string type(in_.token("a type"));
      skip_values(n * dim, type);
      continue;
    }
    if (keyword == "lookup_table") {
      in_.token("a name");
      const uint64_t size = in_.count("the table size", in_.remaining());
      if (binary_) {
        in_.skip_newline();
        in_.skip_bytes(size * 4, "a lookup table");
      } else {
        skip_values(size * 4, "float");
      }
      continue;
    }
    if (keyword == "metadata") {
      skip_metadata();
      continue;
    }
    // Not an attribute: let the caller read it.
    in_.seek(mark);  // the token did not cross a line: the line count still holds
    return;
  }
}

Mesh LegacyReader::read() {
  if (!detail::starts_with_ci(in_.data(), "# vtk DataFile Version"))
    in_.fail("not a legacy VTK file (no '# vtk DataFile Version' line)");
  in_.rest_of_line();
  in_.rest_of_line();  // title
  const std::string_view fmt = in_.token("ASCII or BINARY");
  if (detail::iequals(fmt, "BINARY")) binary_ = true;
  else if (!detail::iequals(fmt, "ASCII")) in_.fail("expected ASCII or BINARY, found '" + std::string(fmt.substr(0, 40)) + "'");
  expect_word("DATASET");
  const std::string_view dataset = in_.token("the dataset type");
  polydata_ = detail::iequals(dataset, "POLYDATA");
  if (!detail::iequals(dataset, "UNSTRUCTURED_GRID") && !polydata_)
    in_.fail("dataset " + std::string(dataset.substr(0, 40)) +
             " is not supported (UNSTRUCTURED_GRID and POLYDATA are)");
  while (!in_.at_end()) {
    const std::string keyword = detail::to_lower(in_.token("a section keyword"));
    if (keyword == "points") {
      read_points();
    } else if (keyword == "cells" && !polydata_) {
      read_cells();
    } else if (polydata_ && (keyword == "vertices" || keyword == "lines" || keyword == "polygons" ||
                             keyword == "triangle_strips")) {
      read_cells(keyword);
    } else if (keyword == "cell_types" && !polydata_) {
      read_cell_types();
      build_elements();
    } else if (keyword == "cell_data") {
      data_seen_ = true;
      attributes(in_.count("the number of cells"), true);
    } else if (keyword == "point_data") {
      data_seen_ = true;
      attributes(in_.count("the number of points"), false);
    } else if (keyword == "field" || keyword == "metadata") {
      in_.seek(in_.pos() - keyword.size());
      attributes(0, false, true);
    } else {
      in_.fail("unexpected keyword '" + keyword.substr(0, 40) + "'");
    }
  }
  if (polydata_ && !have_cells_ && !m_.points.empty()) in_.fail("POLYDATA without POLYGONS or TRIANGLE_STRIPS");
  if (have_cells_ != have_types_ || (!have_cells_ && !m_.points.empty())) in_.fail("CELLS or CELL_TYPES missing");
  if (have_cells_ && !built_) build_elements();
  if (!pending_.empty()) in_.fail("CELL_DATA without the cells");
  detail::require_valid(m_, in_.name());
  detail::sides_from_tets(m_);
  return std::move(m_);
}

Mesh read_vtk(const std::string& path) {
  const detail::FileBytes data(path);
  return LegacyReader(data, path).read();
}

void write_vtk(const Mesh& m, const std::string& path, const WriteOptions& options) {
  const bool bin = options.binary;
  const detail::VtkCellView c(m);
  const size_t ncells = c.size();
  detail::Out out(path);
  out << "# vtk DataFile Version 3.0\nwritten by vdmesh\n" << (bin ? "BINARY" : "ASCII")
      << "\nDATASET UNSTRUCTURED_GRID\n";
  // Region and face names in the data set's field data (vtk_common.h).
  const std::string names = detail::vtk_names_text(m);
  if (!names.empty()) {
    out << "FIELD FieldData 1\n" << detail::kVtkNamesArray << " 1 " << names.size() << " unsigned_char\n";
    if (bin) {
      for (char ch : names) out.raw_be(static_cast<uint8_t>(ch));
      out << '\n';
    } else {
      detail::write_text_values(out, names.size(), 12,
                                [&](size_t i) { return static_cast<int>(static_cast<unsigned char>(names[i])); });
    }
  }
  out << "POINTS " << m.points.size() << " double\n";
  for (const Vec3& p : m.points) {
    if (bin) out.raw_be(p.x), out.raw_be(p.y), out.raw_be(p.z);
    else out << p.x << ' ' << p.y << ' ' << p.z << '\n';
  }
  if (bin) out << '\n';
  out << "CELLS " << ncells << ' ' << ncells + c.connectivity_size() << '\n';
  for (size_t i = 0; i < ncells; ++i) {
    const int k = c.nodes(i);
    if (bin) out.raw_be(static_cast<int32_t>(k));
    else out << k;
    for (int j = 0; j < k; ++j) {
      const int32_t v = c.node(i, j);
      if (bin) out.raw_be(v);
      else out << ' ' << v;
    }
    if (!bin) out << '\n';
  }
  if (bin) out << '\n';
  out << "CELL_TYPES " << ncells << '\n';
  for (size_t i = 0; i < ncells; ++i) {
    if (bin) out.raw_be(static_cast<int32_t>(c.type(i)));
    else out << c.type(i) << '\n';
  }
  if (bin) out << '\n';
  out << "CELL_DATA " << ncells << '\n';
  for (int a = 0; a < 4; ++a) {
    out << "SCALARS " << detail::VtkCellView::kDataNames[a] << " int 1\nLOOKUP_TABLE default\n";
    for (size_t i = 0; i < ncells; ++i) {
      if (bin) out.raw_be(static_cast<int32_t>(c.data(a, i)));
      else out << c.data(a, i) << '\n';
    }
    if (bin) out << '\n';
  }
  out.finish();
}

}  // namespace

Format make_vtk_format() { return {"vtk", {".vtk"}, true, read_vtk, write_vtk, {}}; }

}  // namespace vd::io
