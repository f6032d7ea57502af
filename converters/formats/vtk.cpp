// Legacy VTK (.vtk), ASCII and binary (big-endian), DATASET UNSTRUCTURED_GRID.
// Writes the classic CELLS layout (version 3.0, which Gmsh and VTK 9 read);
// reads it and the 5.1 OFFSETS/CONNECTIVITY layout. Cell data: "region",
// "face", "front", "back" (int).
#include <cmath>

#include "formats.h"
#include "io_util.h"
#include "vtk_common.h"

namespace vd::io {
namespace {

using detail::Cursor;
using detail::FileBytes;

size_t binary_size(std::string_view type) {
  const std::string t = detail::to_lower(type);
  if (t == "bit") return 0;
  if (t == "char" || t == "unsigned_char") return 1;
  if (t == "short" || t == "unsigned_short") return 2;
  if (t == "int" || t == "unsigned_int" || t == "float" || t == "vtktypeint32" || t == "vtktypeuint32") return 4;
  if (t == "long" || t == "unsigned_long" || t == "double" || t == "vtktypeint64" || t == "vtktypeuint64" ||
      t == "vtkidtype")
    return 8;
  return 0;
}

class LegacyReader {
 public:
  LegacyReader(const FileBytes& data, const std::string& path) : in_(data, path) {}
  Mesh read();

 private:
  // `count` values of `type`, as doubles (or skipped when out is null).
  void values(uint64_t count, std::string_view type, std::vector<double>* out);
  void ints(uint64_t count, std::string_view type, std::vector<int64_t>& out);
  void attributes(uint64_t n, bool cell_data);
  void expect_word(std::string_view w);

  Cursor in_;
  bool binary_ = false;
  detail::VtkCells cells_;
  std::vector<Vec3> points_;
};

void LegacyReader::expect_word(std::string_view w) {
  const std::string_view t = in_.token(std::string(w).c_str());
  if (!detail::iequals(t, w)) in_.fail("expected " + std::string(w) + ", found '" + std::string(t.substr(0, 40)) + "'");
}

void LegacyReader::values(uint64_t count, std::string_view type, std::vector<double>* out) {
  if (out) out->reserve(detail::capped(count, in_.remaining(), binary_ ? 1 : 2));
  if (!binary_) {
    for (uint64_t i = 0; i < count; ++i) {
      const std::string_view t = in_.token("a data value");
      double v;
      if (!Cursor::parse_real(t, v)) {
        // Data arrays may hold nan; coordinates are checked by the caller.
        if (detail::iequals(t, "nan") || detail::iequals(t, "-nan")) v = NAN;
        else in_.fail("expected a number, found '" + std::string(t.substr(0, 40)) + "'");
      }
      if (out) out->push_back(v);
    }
    return;
  }
  const size_t size = binary_size(type);
  if (size == 0) in_.fail("unsupported binary data type '" + std::string(type.substr(0, 40)) + "'");
  in_.skip_newline();
  if (count > in_.remaining() / size) in_.fail("file ends inside a data array of " + std::to_string(count) + " values");
  const std::string t = detail::to_lower(type);
  for (uint64_t i = 0; i < count && out; ++i) {
    double v;
    if (t == "float") v = in_.get_be<float>("a value");
    else if (t == "double") v = in_.get_be<double>("a value");
    else if (t == "char") v = in_.get<int8_t>("a value");
    else if (t == "unsigned_char") v = in_.get<uint8_t>("a value");
    else if (t == "short") v = in_.get_be<int16_t>("a value");
    else if (t == "unsigned_short") v = in_.get_be<uint16_t>("a value");
    else if (size == 4 && t.find("unsigned") == std::string::npos && t != "vtktypeuint32") v = in_.get_be<int32_t>("a value");
    else if (size == 4) v = in_.get_be<uint32_t>("a value");
    else if (t == "unsigned_long" || t == "vtktypeuint64") v = static_cast<double>(in_.get_be<uint64_t>("a value"));
    else v = static_cast<double>(in_.get_be<int64_t>("a value"));
    out->push_back(v);
  }
  if (!out) in_.skip_bytes(count * size, "a data array");
}

void LegacyReader::ints(uint64_t count, std::string_view type, std::vector<int64_t>& out) {
  out.reserve(detail::capped(count, in_.remaining(), binary_ ? 4 : 2));
  if (!binary_) {
    for (uint64_t i = 0; i < count; ++i) out.push_back(in_.integer("a cell index"));
    return;
  }
  const size_t size = binary_size(type);
  if (size != 4 && size != 8) in_.fail("cell indices must be 4 or 8 byte integers");
  in_.skip_newline();
  if (count > in_.remaining() / size) in_.fail("file ends inside the cells");
  for (uint64_t i = 0; i < count; ++i)
    out.push_back(size == 4 ? in_.get_be<int32_t>("a cell index") : in_.get_be<int64_t>("a cell index"));
}

void LegacyReader::attributes(uint64_t n, bool cell_data) {
  // Runs until the next CELL_DATA / POINT_DATA or the end of the file.
  for (;;) {
    if (in_.at_end()) return;
    const size_t mark = in_.pos();
    const std::string keyword = detail::to_lower(in_.token("a data keyword"));
    std::vector<double> arr;
    std::vector<double>* keep = nullptr;
    if (keyword == "scalars") {
      const std::string name(in_.token("a scalars name"));
      const std::string type(in_.token("a scalars type"));
      uint64_t ncomp = 1;
      if (in_.line_has_more()) ncomp = in_.count("the number of components", 4);
      if (ncomp == 0) in_.fail("zero components");
      std::string_view look = in_.token("LOOKUP_TABLE");
      if (!detail::iequals(look, "LOOKUP_TABLE")) in_.fail("expected LOOKUP_TABLE");
      in_.token("a lookup table name");
      keep = cell_data && ncomp == 1 ? &cells_.data[name] : nullptr;
      if (keep) keep->clear();
      values(n * ncomp, type, keep);
      continue;
    }
    if (keyword == "field") {
      in_.token("a field name");
      const uint64_t arrays = in_.count("the number of arrays", 1 << 20);
      for (uint64_t a = 0; a < arrays; ++a) {
        const std::string name(in_.token("an array name"));
        const uint64_t ncomp = in_.count("the number of components", 1 << 20);
        const uint64_t tuples = in_.count("the number of tuples");
        const std::string type(in_.token("an array type"));
        if (ncomp == 0 || tuples > in_.remaining()) in_.fail("bad field array size");
        keep = cell_data && ncomp == 1 && tuples == n ? &cells_.data[name] : nullptr;
        if (keep) keep->clear();
        values(ncomp * tuples, type, keep);
      }
      continue;
    }
    if (keyword == "vectors" || keyword == "normals" || keyword == "tensors") {
      in_.token("a name");
      const std::string type(in_.token("a type"));
      values(n * (keyword == "tensors" ? 9 : 3), type, nullptr);
      continue;
    }
    if (keyword == "texture_coordinates") {
      in_.token("a name");
      const uint64_t dim = in_.count("the dimension", 3);
      const std::string type(in_.token("a type"));
      values(n * dim, type, nullptr);
      continue;
    }
    if (keyword == "lookup_table") {
      in_.token("a name");
      const uint64_t size = in_.count("the table size", in_.remaining());
      if (binary_) {
        in_.skip_newline();
        in_.skip_bytes(size * 4, "a lookup table");
      } else {
        values(size * 4, "float", nullptr);
      }
      continue;
    }
    if (keyword == "metadata") {
      // Lines of information up to an empty line.
      in_.skip_line();
      while (in_.pos() < in_.data().size() && !in_.rest_of_line().empty()) {
      }
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
  if (!detail::iequals(dataset, "UNSTRUCTURED_GRID"))
    in_.fail("dataset " + std::string(dataset.substr(0, 40)) + " is not supported (UNSTRUCTURED_GRID is)");
  bool have_cells = false, have_types = false;
  while (!in_.at_end()) {
    const std::string keyword = detail::to_lower(in_.token("a section keyword"));
    if (keyword == "points") {
      const uint64_t n = in_.count("the number of points", in_.remaining());
      const std::string type(in_.token("the point type"));
      std::vector<double> xyz;
      values(3 * n, type, &xyz);
      points_.reserve(n);
      for (uint64_t i = 0; i < n; ++i) {
        const Vec3 p{xyz[3 * i], xyz[3 * i + 1], xyz[3 * i + 2]};
        if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
          in_.fail("point " + std::to_string(i) + " has a coordinate that is not a finite number");
        points_.push_back(p);
      }
    } else if (keyword == "cells") {
      const uint64_t a = in_.count("the number of cells", in_.remaining());
      const uint64_t b = in_.count("the cell list size", in_.remaining());
      // Peek at the next token; at_end() first so seeking back crosses no line.
      if (in_.at_end()) in_.fail("unexpected end of file in CELLS");
      const size_t mark = in_.pos();
      const std::string_view next = in_.token("the cells");
      if (detail::iequals(next, "OFFSETS")) {
        // Version 5: a offsets, then b connectivity entries.
        const std::string otype(in_.token("the offset type"));
        ints(a, otype, cells_.offsets);
        expect_word("CONNECTIVITY");
        const std::string ctype(in_.token("the connectivity type"));
        ints(b, ctype, cells_.conn);
        if (cells_.offsets.empty() || cells_.offsets.front() != 0) in_.fail("offsets must start with 0");
      } else {
        in_.seek(mark);
        std::vector<int64_t> list;
        ints(b, "int", list);
        cells_.offsets.assign(1, 0);
        size_t at = 0;
        for (uint64_t i = 0; i < a; ++i) {
          if (at >= list.size()) in_.fail("the cell list is shorter than its " + std::to_string(a) + " cells");
          const int64_t k = list[at++];
          if (k < 0 || static_cast<uint64_t>(k) > list.size() - at) in_.fail("cell " + std::to_string(i) + " has a bad size");
          for (int64_t j = 0; j < k; ++j) cells_.conn.push_back(list[at++]);
          cells_.offsets.push_back(static_cast<int64_t>(cells_.conn.size()));
        }
        if (at != list.size()) in_.fail("the cell list size does not match its cells");
      }
      have_cells = true;
      // Checked here, while the line is known (points come first in VTK).
      for (int64_t v : cells_.conn)
          if (v < 0 || static_cast<uint64_t>(v) >= points_.size())
            in_.fail("a cell refers to point " + std::to_string(v) + ", which does not exist (" +
                     std::to_string(points_.size()) + " points)");
    } else if (keyword == "cell_types") {
      const uint64_t n = in_.count("the number of cell types", in_.remaining());
      std::vector<int64_t> t;
      ints(n, "int", t);
      for (int64_t v : t) cells_.types.push_back(static_cast<int>(v));
      have_types = true;
    } else if (keyword == "cell_data") {
      attributes(in_.count("the number of cells"), true);
    } else if (keyword == "point_data") {
      attributes(in_.count("the number of points"), false);
    } else if (keyword == "field" || keyword == "metadata") {
      in_.seek(in_.pos() - keyword.size());
      attributes(0, false);
    } else {
      in_.fail("unexpected keyword '" + keyword.substr(0, 40) + "'");
    }
  }
  if (!have_cells || !have_types) {
    if (!points_.empty() || have_cells || have_types) in_.fail("CELLS or CELL_TYPES missing");
  }
  if (cells_.offsets.empty()) cells_.offsets.push_back(0);
  if (cells_.types.size() + 1 != cells_.offsets.size())
    in_.fail("CELL_TYPES has " + std::to_string(cells_.types.size()) + " entries for " +
             std::to_string(cells_.offsets.size() - 1) + " cells");
  return detail::mesh_from_vtk(std::move(points_), cells_, in_.name());
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
      << "\nDATASET UNSTRUCTURED_GRID\nPOINTS " << m.points.size() << " double\n";
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

Format make_vtk_format() { return {"vtk", {".vtk"}, true, read_vtk, write_vtk}; }

}  // namespace vd::io
