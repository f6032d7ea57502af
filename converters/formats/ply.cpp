// Stanford PLY, ASCII and binary (little- and big-endian): a surface of
// polygons, triangulated as OFF's are (triangulate_polygon). The "vertex"
// element's x, y, z, the "face" element's vertex_indices (or vertex_index)
// list and the "tristrips" element's vertex_indices (strips of the old
// scanner files, -1 between strips) are read, every other element and
// property skipped; face properties "face", "front" and "back" give the
// tags, which the writer writes (ASCII, or binary little-endian with
// --binary). Strips have no tags.
#include <cmath>
#include <cstdio>

#include "formats.h"
#include "io_util.h"
#include "polygon_triangulation.h"

namespace vd::io {
namespace {

using detail::Cursor;

enum class Type { Int8, UInt8, Int16, UInt16, Int32, UInt32, Float32, Float64, Unknown };

// PLY's type names, the original and the sized ones (int8 ... float64).
Type type_named(std::string_view t) {
  if (t == "char" || t == "int8") return Type::Int8;
  if (t == "uchar" || t == "uint8") return Type::UInt8;
  if (t == "short" || t == "int16") return Type::Int16;
  if (t == "ushort" || t == "uint16") return Type::UInt16;
  if (t == "int" || t == "int32") return Type::Int32;
  if (t == "uint" || t == "uint32") return Type::UInt32;
  if (t == "float" || t == "float32") return Type::Float32;
  if (t == "double" || t == "float64") return Type::Float64;
  return Type::Unknown;
}

struct Property {
  std::string name;
  Type type = Type::Unknown;        // of the value, or of a list's items
  Type count_type = Type::Unknown;  // a list's length; Unknown: not a list
  bool is_list() const { return count_type != Type::Unknown; }
};

struct Element {
  std::string name;
  uint64_t count = 0;
  std::vector<Property> properties;
};

enum class Encoding { Ascii, Little, Big };

class PlyReader {
 public:
  PlyReader(const detail::FileBytes& data, const std::string& path) : in_(data, path) {}
  Mesh read();

 private:
  void read_header();
  // One value of `type`: a number token in ASCII, else its bytes.
  double value(Type type, const char* what);
  // A list's length or a vertex index: a whole number within [0, limit].
  uint64_t whole(Type type, uint64_t limit, const char* what);
  void read_vertices(const Element& e);
  void read_faces(const Element& e);
  void read_strips(const Element& e);
  void skip_element(const Element& e);

  Cursor in_;
  Encoding encoding_ = Encoding::Ascii;
  std::vector<Element> elements_;
  Mesh m_;
  bool have_vertices_ = false;
};

void PlyReader::read_header() {
  // Token by token, so that an error names the header line it is on.
  if (in_.token("the 'ply' line") != "ply") in_.fail("not a PLY file (it does not start with 'ply')");
  in_.rest_of_line();
  bool have_format = false;
  for (;;) {
    if (in_.at_end()) in_.fail("the header has no end_header line");
    std::vector<std::string_view> w{in_.token("a header keyword")};
    if (w[0] == "comment" || w[0] == "obj_info") {
      in_.rest_of_line();
      continue;
    }
    while (in_.line_has_more()) w.push_back(in_.token_in_line());
    if (w[0] == "end_header") {
      in_.rest_of_line();  // the data starts on the next line
      break;
    }
    if (w[0] == "format") {
      if (w.size() < 3) in_.fail("a format line needs an encoding and a version");
      if (w[1] == "ascii") encoding_ = Encoding::Ascii;
      else if (w[1] == "binary_little_endian") encoding_ = Encoding::Little;
      else if (w[1] == "binary_big_endian") encoding_ = Encoding::Big;
      else in_.fail("unknown PLY format '" + std::string(w[1].substr(0, 40)) + "'");
      if (w[2] != "1.0") in_.fail("PLY version " + std::string(w[2].substr(0, 20)) + " (1.0 is read)");
      have_format = true;
    } else if (w[0] == "element") {
      int64_t n;
      if (w.size() != 3 || !Cursor::parse_int(w[2], n) || n < 0)
        in_.fail("an element line needs a name and a count");
      elements_.push_back({std::string(w[1]), static_cast<uint64_t>(n), {}});
    } else if (w[0] == "property") {
      if (elements_.empty()) in_.fail("a property before any element");
      Property p;
      if (w.size() == 5 && w[1] == "list") {
        p.count_type = type_named(w[2]);
        p.type = type_named(w[3]);
        p.name = w[4];
        if (p.count_type == Type::Unknown || p.count_type == Type::Float32 || p.count_type == Type::Float64)
          in_.fail("a list's length type must be an integer type, not '" + std::string(w[2].substr(0, 20)) + "'");
      } else if (w.size() == 3) {
        p.type = type_named(w[1]);
        p.name = w[2];
      } else {
        in_.fail("a property line is 'property TYPE NAME' or 'property list TYPE TYPE NAME'");
      }
      if (p.type == Type::Unknown) in_.fail("unknown property type in property " + p.name.substr(0, 40));
      elements_.back().properties.push_back(std::move(p));
    } else {
      in_.fail("unknown header keyword '" + std::string(w[0].substr(0, 40)) + "'");
    }
    in_.rest_of_line();
  }
  if (!have_format) in_.fail("the header has no format line");
}

double PlyReader::value(Type type, const char* what) {
  if (encoding_ == Encoding::Ascii) {
    const std::string_view t = in_.token(what);
    double v;
    if (!Cursor::parse_real(t, v)) in_.fail(std::string("expected ") + what + ", found '" + std::string(t.substr(0, 40)) + "'");
    return v;
  }
  const bool big = encoding_ == Encoding::Big;
  switch (type) {
    case Type::Int8: return in_.get<int8_t>(what);
    case Type::UInt8: return in_.get<uint8_t>(what);
    case Type::Int16: return big ? in_.get_be<int16_t>(what) : in_.get<int16_t>(what);
    case Type::UInt16: return big ? in_.get_be<uint16_t>(what) : in_.get<uint16_t>(what);
    case Type::Int32: return big ? in_.get_be<int32_t>(what) : in_.get<int32_t>(what);
    case Type::UInt32: return big ? in_.get_be<uint32_t>(what) : in_.get<uint32_t>(what);
    case Type::Float32: return big ? in_.get_be<float>(what) : in_.get<float>(what);
    default: return big ? in_.get_be<double>(what) : in_.get<double>(what);
  }
}

uint64_t PlyReader::whole(Type type, uint64_t limit, const char* what) {
  const double v = value(type, what);
  if (!(v >= 0 && v <= static_cast<double>(limit)) || v != std::floor(v)) {
    char text[32];
    std::snprintf(text, sizeof text, "%g", v);
    in_.fail(std::string(what) + " " + text + " is not a whole number from 0 to " + std::to_string(limit));
  }
  return static_cast<uint64_t>(v);
}

void PlyReader::read_vertices(const Element& e) {
  if (have_vertices_) in_.fail("a second vertex element");
  int axis[3] = {-1, -1, -1};
  for (size_t i = 0; i < e.properties.size(); ++i) {
    const Property& p = e.properties[i];
    for (int k = 0; k < 3; ++k)
      if (p.name == std::string(1, static_cast<char>('x' + k))) {
        if (p.is_list()) in_.fail("vertex property " + p.name + " is a list");
        axis[k] = static_cast<int>(i);
      }
  }
  if (axis[0] < 0 || axis[1] < 0 || axis[2] < 0) in_.fail("the vertex element lacks one of x, y, z");
  m_.points.reserve(detail::capped(e.count, in_.remaining(), 3));
  for (uint64_t v = 0; v < e.count; ++v) {
    Vec3 p;
    for (size_t i = 0; i < e.properties.size(); ++i) {
      const Property& prop = e.properties[i];
      if (prop.is_list()) {
        const uint64_t n = whole(prop.count_type, in_.remaining(), "a list length");
        for (uint64_t j = 0; j < n; ++j) value(prop.type, "a list item");
        continue;
      }
      const double x = value(prop.type, "a vertex value");
      for (int k = 0; k < 3; ++k)
        if (axis[k] == static_cast<int>(i)) {
          if (!std::isfinite(x)) in_.fail("vertex " + std::to_string(v) + " has a coordinate that is not a finite number");
          p[k] = x;
        }
    }
    m_.points.push_back(p);
  }
  have_vertices_ = true;
}

void PlyReader::read_faces(const Element& e) {
  if (!have_vertices_) in_.fail("the face element comes before the vertex element");
  int indices = -1, face = -1, front = -1, back = -1;
  for (size_t i = 0; i < e.properties.size(); ++i) {
    const Property& p = e.properties[i];
    if ((p.name == "vertex_indices" || p.name == "vertex_index") && p.is_list()) indices = static_cast<int>(i);
    if (!p.is_list() && p.name == "face") face = static_cast<int>(i);
    if (!p.is_list() && p.name == "front") front = static_cast<int>(i);
    if (!p.is_list() && p.name == "back") back = static_cast<int>(i);
  }
  if (indices < 0) in_.fail("the face element has no vertex_indices list");
  const uint64_t nv = m_.points.size();
  m_.triangles.reserve(detail::capped(e.count, in_.remaining(), 4));
  std::vector<int> polygon;
  for (uint64_t f = 0; f < e.count; ++f) {
    Triangle tags;
    polygon.clear();
    for (size_t i = 0; i < e.properties.size(); ++i) {
      const Property& prop = e.properties[i];
      if (prop.is_list()) {
        const uint64_t n = whole(prop.count_type, in_.remaining(), "a list length");
        for (uint64_t j = 0; j < n; ++j) {
          if (static_cast<int>(i) != indices) {
            value(prop.type, "a list item");
            continue;
          }
          const uint64_t v = whole(prop.type, UINT64_C(1) << 40, "a face vertex index");
          if (v >= nv) in_.fail("face " + std::to_string(f) + " refers to vertex " + std::to_string(v) +
                                ", which does not exist (" + std::to_string(nv) + " vertices)");
          polygon.push_back(static_cast<int>(v));
        }
        continue;
      }
      const double x = value(prop.type, "a face value");
      const int id = x >= -2147483648.0 && x <= 2147483647.0 ? static_cast<int>(x) : kUnknownRegion;
      if (static_cast<int>(i) == face) tags.face = id < 0 ? kNoFace : id;
      if (static_cast<int>(i) == front) tags.front = id;
      if (static_cast<int>(i) == back) tags.back = id;
    }
    if (polygon.size() < 3) in_.fail("face " + std::to_string(f) + " has " + std::to_string(polygon.size()) + " vertices");
    for (const auto& corners : detail::triangulate_polygon(m_.points, polygon)) {
      Triangle t = tags;
      t.v = corners;
      m_.triangles.push_back(t);
    }
  }
}

void PlyReader::read_strips(const Element& e) {
  if (!have_vertices_) in_.fail("the tristrips element comes before the vertex element");
  int indices = -1;
  for (size_t i = 0; i < e.properties.size(); ++i)
    if (e.properties[i].name == "vertex_indices" && e.properties[i].is_list()) indices = static_cast<int>(i);
  if (indices < 0) in_.fail("the tristrips element has no vertex_indices list");
  const double nv = static_cast<double>(m_.points.size());
  std::vector<int> strip;
  const auto end_strip = [&] {
    for (const auto& corners : detail::strip_triangles(strip.data(), strip.size())) {
      Triangle t;
      t.v = corners;
      m_.triangles.push_back(t);
    }
    strip.clear();
  };
  for (uint64_t r = 0; r < e.count; ++r) {
    for (size_t i = 0; i < e.properties.size(); ++i) {
      const Property& prop = e.properties[i];
      if (!prop.is_list()) {
        value(prop.type, "a tristrips value");
        continue;
      }
      const uint64_t n = whole(prop.count_type, in_.remaining(), "a list length");
      for (uint64_t j = 0; j < n; ++j) {
        const double v = value(prop.type, "a strip vertex index");
        if (static_cast<int>(i) != indices) continue;
        // -1 ends a strip; an unsigned list writes it as its largest value.
        if (v == -1 || (prop.type == Type::UInt32 && v == 4294967295.0)) {
          end_strip();
        } else if (v >= 0 && v < nv && v == std::floor(v)) {
          strip.push_back(static_cast<int>(v));
        } else {
          char text[32];
          std::snprintf(text, sizeof text, "%.17g", v);
          in_.fail("tristrips " + std::to_string(r) + " refers to vertex " + text + ", which does not exist (" +
                   std::to_string(m_.points.size()) + " vertices; -1 ends a strip)");
        }
      }
      if (static_cast<int>(i) == indices) end_strip();
    }
  }
}

void PlyReader::skip_element(const Element& e) {
  if (e.properties.empty()) return;  // nothing in the data
  for (uint64_t r = 0; r < e.count; ++r)
    for (const Property& p : e.properties) {
      if (!p.is_list()) {
        value(p.type, "a value");
        continue;
      }
      const uint64_t n = whole(p.count_type, in_.remaining(), "a list length");
      for (uint64_t j = 0; j < n; ++j) value(p.type, "a list item");
    }
}

Mesh PlyReader::read() {
  read_header();
  for (const Element& e : elements_) {
    if (e.name == "vertex") read_vertices(e);
    else if (e.name == "face") read_faces(e);
    else if (e.name == "tristrips") read_strips(e);
    else skip_element(e);
  }
  if (!have_vertices_) in_.fail("no vertex element");
  if (m_.triangles.empty()) in_.fail("no faces");
  return std::move(m_);
}

Mesh read_ply(const std::string& path) {
  const detail::FileBytes data(path);
  return PlyReader(data, path).read();
}

// Every triangle with its tags (the sides too: PLY can say them).
void write_ply(const Mesh& m, const std::string& path, const WriteOptions& options) {
  detail::Out out(path);
  const detail::SurfacePoints used = detail::surface_points(m);
  out << "ply\nformat " << (options.binary ? "binary_little_endian" : "ascii") << " 1.0\ncomment written by vdmesh\n"
      << "element vertex " << used.kept.size() << "\nproperty double x\nproperty double y\nproperty double z\n"
      << "element face " << m.triangles.size()
      << "\nproperty list uchar int vertex_indices\nproperty int face\nproperty int front\nproperty int back\n"
      << "end_header\n";
  if (options.binary) {
    for (const int i : used.kept) {
      out.raw(m.points[i].x);
      out.raw(m.points[i].y);
      out.raw(m.points[i].z);
    }
    for (const Triangle& t : m.triangles) {
      out.raw(static_cast<uint8_t>(3));
      for (const int v : t.v) out.raw(static_cast<int32_t>(used.number[v]));
      out.raw(static_cast<int32_t>(t.face));
      out.raw(static_cast<int32_t>(t.front));
      out.raw(static_cast<int32_t>(t.back));
    }
  } else {
    for (const int i : used.kept) out << m.points[i].x << ' ' << m.points[i].y << ' ' << m.points[i].z << '\n';
    for (const Triangle& t : m.triangles)
      out << "3 " << used.number[t.v[0]] << ' ' << used.number[t.v[1]] << ' ' << used.number[t.v[2]] << ' ' << t.face
          << ' ' << t.front << ' ' << t.back << '\n';
  }
  out.finish();
}

}  // namespace

Format make_ply_format() { return {"ply", {".ply"}, false, read_ply, write_ply, {}}; }

}  // namespace vd::io
