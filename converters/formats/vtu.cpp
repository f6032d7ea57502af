// VTK XML unstructured grid (.vtu). Writes inline ASCII or base64 binary with
// header_type="UInt64" declared (VTK aborts on an undeclared 64-bit header).
// Reads inline ascii/binary, zlib-compressed blocks and raw or base64
// appended data, with UInt32 or UInt64 headers.
#include <zlib.h>

#include <array>
#include <cctype>
#include <cmath>

#include "formats.h"
#include "io_util.h"
#include "vtk_common.h"

namespace vd::io {
namespace {

using detail::Cursor;

// ---------------------------------------------------------------------------
// base64

const char kB64[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";

void base64_append(std::string& out, const unsigned char* p, size_t n) {
  out.reserve(out.size() + (n + 2) / 3 * 4);
  size_t i = 0;
  for (; i + 3 <= n; i += 3) {
    const uint32_t v = (uint32_t{p[i]} << 16) | (uint32_t{p[i + 1]} << 8) | p[i + 2];
    const char q[4] = {kB64[v >> 18], kB64[(v >> 12) & 63], kB64[(v >> 6) & 63], kB64[v & 63]};
    out.append(q, 4);
  }
  if (i < n) {
    const uint32_t v = (uint32_t{p[i]} << 16) | (i + 1 < n ? uint32_t{p[i + 1]} << 8 : 0);
    out += kB64[v >> 18];
    out += kB64[(v >> 12) & 63];
    out += i + 1 < n ? kB64[(v >> 6) & 63] : '=';
    out += '=';
  }
}

// Decodes base64, skipping white space and padding; false on a bad character.
bool base64_decode(std::string_view in, std::string& out) {
  static const std::array<int8_t, 256> table = [] {
    std::array<int8_t, 256> t;
    t.fill(-1);
    for (int i = 0; i < 64; ++i) t[static_cast<unsigned char>(kB64[i])] = static_cast<int8_t>(i);
    t['='] = t[' '] = t['\n'] = t['\r'] = t['\t'] = -2;
    return t;
  }();
  out.resize(in.size() / 4 * 3 + 3);
  char* o = out.data();
  const unsigned char* p = reinterpret_cast<const unsigned char*>(in.data());
  const unsigned char* end = p + in.size();
  uint32_t acc = 0;
  int bits = 0;
  // Four characters at a time while they are all data, else one by one.
  while (p < end) {
    if (end - p >= 4) {
      const int a = table[p[0]], b = table[p[1]], c = table[p[2]], d = table[p[3]];
      if ((a | b | c | d) >= 0 && bits == 0) {
        const uint32_t v = (uint32_t(a) << 18) | (uint32_t(b) << 12) | (uint32_t(c) << 6) | uint32_t(d);
        o[0] = static_cast<char>(v >> 16);
        o[1] = static_cast<char>((v >> 8) & 0xFF);
        o[2] = static_cast<char>(v & 0xFF);
        o += 3;
        p += 4;
        continue;
      }
    }
    const int v = table[*p++];
    if (v == -2) continue;
    if (v < 0) return false;
    acc = (acc << 6) | static_cast<uint32_t>(v);
    bits += 6;
    if (bits >= 8) {
      bits -= 8;
      *o++ = static_cast<char>((acc >> bits) & 0xFF);
    }
  }
  out.resize(static_cast<size_t>(o - out.data()));
  return true;
}

// ---------------------------------------------------------------------------
// writer

void write_vtu(const Mesh& m, const std::string& path, const WriteOptions& options) {
  const bool bin = options.binary;
  const detail::VtkCellView c(m);
  const size_t ncells = c.size();
  detail::Out out(path);
  const char* format = bin ? "binary" : "ascii";
  out << "<?xml version=\"1.0\"?>\n"
         "<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\">\n"
         "  <UnstructuredGrid>\n    <Piece NumberOfPoints=\""
      << m.points.size() << "\" NumberOfCells=\"" << ncells << "\">\n";
  // One array: binary is base64 of (byte count as UInt64, raw little-endian data).
  auto array = [&](const char* type, const char* name, int components, size_t n, auto value) {
    out << "        <DataArray type=\"" << type << "\" Name=\"" << name << "\"";
    if (components > 1) out << " NumberOfComponents=\"" << components << "\"";
    out << " format=\"" << format << "\">\n";
    using T = decltype(value(size_t{0}));
    if (bin) {
      // base64 of (byte count, values), encoded a piece of whole 3-byte
      // groups at a time so that the array never exists whole in memory.
      constexpr size_t kPiece = 3 * 16384;
      std::vector<unsigned char> piece;
      piece.reserve(kPiece + 16);
      auto put = [&](const void* p, size_t size) {
        const auto* b = static_cast<const unsigned char*>(p);
        piece.insert(piece.end(), b, b + size);
        if (piece.size() < kPiece) return;
        const size_t whole = piece.size() / 3 * 3;
        base64_append(out.str(), piece.data(), whole);
        piece.erase(piece.begin(), piece.begin() + static_cast<std::ptrdiff_t>(whole));
        out.spill_if_full();
      };
      const uint64_t bytes = n * sizeof(T);
      out << "          ";
      put(&bytes, sizeof bytes);
      for (size_t i = 0; i < n; ++i) {
        const T v = value(i);
        put(&v, sizeof v);
      }
      base64_append(out.str(), piece.data(), piece.size());
      out << '\n';
    } else {
      for (size_t i = 0; i < n; ++i) {
        const T v = value(i);
        if constexpr (sizeof(T) == 1) out << static_cast<int>(v);
        else if constexpr (std::is_floating_point_v<T>) out << static_cast<double>(v);
        else out << static_cast<long long>(v);
        out << ((i + 1) % 12 == 0 || i + 1 == n ? '\n' : ' ');
      }
    }
    out << "        </DataArray>\n";
  };
  out << "      <Points>\n";
  array("Float64", "Points", 3, 3 * m.points.size(),
        [&](size_t i) { return m.points[i / 3][static_cast<int>(i % 3)]; });
  out << "      </Points>\n      <Cells>\n";
  // The connectivity is asked for in order, so a running (cell, node) pair
  // stands for its flat index.
  size_t cell = 0;
  int node = 0;
  array("Int64", "connectivity", 1, c.connectivity_size(), [&](size_t) {
    const int64_t v = c.node(cell, node);
    if (++node == c.nodes(cell)) node = 0, ++cell;
    return v;
  });
  array("Int64", "offsets", 1, ncells, [&](size_t i) { return c.end(i); });
  array("UInt8", "types", 1, ncells, [&](size_t i) { return static_cast<uint8_t>(c.type(i)); });
  out << "      </Cells>\n      <CellData>\n";
  for (int a = 0; a < 4; ++a)
    array("Int32", detail::VtkCellView::kDataNames[a], 1, ncells,
          [&](size_t i) { return static_cast<int32_t>(c.data(a, i)); });
  out << "      </CellData>\n    </Piece>\n  </UnstructuredGrid>\n</VTKFile>\n";
  out.finish();
}

// ---------------------------------------------------------------------------
// reader

struct Tag {
  std::string name;
  std::map<std::string, std::string> attrs;
  size_t begin = 0;        // offset of '<'
  size_t content = 0;      // offset after '>'
  bool closing = false, self_closing = false;
};

class VtuReader {
 public:
  VtuReader(std::string_view data, const std::string& path) : d_(data), path_(path) {}
  Mesh read();

 private:
  [[noreturn]] void fail(size_t offset, const std::string& what) const {
    size_t line = 1;
    for (size_t i = 0; i < offset && i < d_.size(); ++i) line += d_[i] == '\n';
    throw InputError(path_ + ":" + std::to_string(line) + ": " + what);
  }
  bool next_tag(Tag& t);
  std::string attr(const Tag& t, const char* name, const char* fallback = nullptr) const;
  // The values of one DataArray, converted to T.
  template <class T>
  std::vector<T> values(const Tag& t, uint64_t expected);
  std::string decoded_bytes(const Tag& t, std::string_view text, size_t elem_size, uint64_t expected);

  std::string_view d_;
  std::string path_;
  size_t pos_ = 0;
  size_t header_size_ = 4;  // UInt32 unless declared
  bool compressed_ = false;
  size_t appended_ = std::string_view::npos;  // offset after '_'
  bool appended_base64_ = false;
};

bool VtuReader::next_tag(Tag& t) {
  for (;;) {
    const size_t lt = d_.find('<', pos_);
    if (lt == std::string_view::npos) return false;
    pos_ = lt + 1;
    if (d_.compare(lt, 4, "<!--") == 0) {
      const size_t end = d_.find("-->", lt);
      if (end == std::string_view::npos) fail(lt, "comment not closed");
      pos_ = end + 3;
      continue;
    }
    if (d_.compare(lt, 2, "<?") == 0) {
      const size_t end = d_.find("?>", lt);
      if (end == std::string_view::npos) fail(lt, "declaration not closed");
      pos_ = end + 2;
      continue;
    }
    t = Tag();
    t.begin = lt;
    size_t i = lt + 1;
    if (i < d_.size() && d_[i] == '/') t.closing = true, ++i;
    const size_t name_start = i;
    while (i < d_.size() && !std::isspace(static_cast<unsigned char>(d_[i])) && d_[i] != '>' && d_[i] != '/') ++i;
    t.name = std::string(d_.substr(name_start, i - name_start));
    for (;;) {
      while (i < d_.size() && std::isspace(static_cast<unsigned char>(d_[i]))) ++i;
      if (i >= d_.size()) fail(lt, "tag <" + t.name + "> not closed");
      if (d_[i] == '>') {
        ++i;
        break;
      }
      if (d_[i] == '/' && i + 1 < d_.size() && d_[i + 1] == '>') {
        t.self_closing = true;
        i += 2;
        break;
      }
      const size_t key_start = i;
      while (i < d_.size() && d_[i] != '=' && d_[i] != '>' && !std::isspace(static_cast<unsigned char>(d_[i]))) ++i;
      const std::string key(d_.substr(key_start, i - key_start));
      while (i < d_.size() && std::isspace(static_cast<unsigned char>(d_[i]))) ++i;
      if (i >= d_.size() || d_[i] != '=') fail(lt, "attribute '" + key.substr(0, 40) + "' has no value");
      ++i;
      while (i < d_.size() && std::isspace(static_cast<unsigned char>(d_[i]))) ++i;
      if (i >= d_.size() || (d_[i] != '"' && d_[i] != '\'')) fail(lt, "attribute '" + key.substr(0, 40) + "' not quoted");
      const char q = d_[i++];
      const size_t end = d_.find(q, i);
      if (end == std::string_view::npos) fail(lt, "attribute value not closed");
      t.attrs[key] = std::string(d_.substr(i, end - i));
      i = end + 1;
    }
    t.content = i;
    pos_ = i;
    return true;
  }
}

std::string VtuReader::attr(const Tag& t, const char* name, const char* fallback) const {
  auto it = t.attrs.find(name);
  if (it != t.attrs.end()) return it->second;
  if (!fallback) fail(t.begin, "<" + t.name + "> has no " + name + " attribute");
  return fallback;
}

size_t type_size(const std::string& type) {
  if (type == "Int8" || type == "UInt8") return 1;
  if (type == "Int16" || type == "UInt16") return 2;
  if (type == "Int32" || type == "UInt32" || type == "Float32") return 4;
  if (type == "Int64" || type == "UInt64" || type == "Float64") return 8;
  return 0;
}

template <class T>
T convert(const char* p, const std::string& type) {
  auto load = [p](auto v) {
    std::memcpy(&v, p, sizeof v);
    return static_cast<T>(v);
  };
  if (type == "Int8") return load(int8_t{});
  if (type == "UInt8") return load(uint8_t{});
  if (type == "Int16") return load(int16_t{});
  if (type == "UInt16") return load(uint16_t{});
  if (type == "Int32") return load(int32_t{});
  if (type == "UInt32") return load(uint32_t{});
  if (type == "Int64") return load(int64_t{});
  if (type == "UInt64") {
    uint64_t v;
    std::memcpy(&v, p, 8);
    return static_cast<T>(v > uint64_t{INT64_MAX} ? INT64_MAX : v);
  }
  if (type == "Float32") {
    float v;
    std::memcpy(&v, p, 4);
    if constexpr (std::is_integral_v<T>) return std::isfinite(v) && std::abs(v) < 9e18f ? static_cast<T>(v) : T(-1);
    return static_cast<T>(v);
  }
  double v;
  std::memcpy(&v, p, 8);
  if constexpr (std::is_integral_v<T>) return std::isfinite(v) && std::abs(v) < 9e18 ? static_cast<T>(v) : T(-1);
  return static_cast<T>(v);
}

uint64_t header_value(const char* p, size_t size) {
  if (size == 8) {
    uint64_t v;
    std::memcpy(&v, p, 8);
    return v;
  }
  uint32_t v;
  std::memcpy(&v, p, 4);
  return v;
}

// Binary data of one array: header (+ compressed blocks) already base64-decoded
// or raw; returns the payload bytes.
std::string VtuReader::decoded_bytes(const Tag& t, std::string_view text, size_t elem_size, uint64_t expected) {
  const size_t hs = header_size_;
  std::string bytes;
  const std::string format = attr(t, "format");
  const bool base64 = format == "binary" || (format == "appended" && appended_base64_);
  std::string_view src;
  std::string decoded;
  if (format == "appended") {
    const uint64_t offset = std::strtoull(attr(t, "offset").c_str(), nullptr, 10);
    if (appended_ == std::string_view::npos || offset > d_.size() - appended_) fail(t.begin, "bad appended data offset");
    src = d_.substr(appended_ + static_cast<size_t>(offset));
  } else {
    src = text;
  }
  // Base64 text is measured in characters below: start at the first one
  // (raw appended bytes are taken as they are).
  if (base64)
    while (!src.empty() && std::isspace(static_cast<unsigned char>(src.front()))) src.remove_prefix(1);
  if (!compressed_) {
    if (base64) {
      // The header alone tells how much to decode (appended arrays run on).
      if (!base64_decode(format == "appended" ? src.substr(0, std::min(src.size(), (hs + 2) / 3 * 4)) : src, decoded))
        fail(t.content, "bad base64 data");
      if (format == "appended") {
        if (decoded.size() < hs) fail(t.begin, "appended data too short");
        const uint64_t n = header_value(decoded.data(), hs);
        if (n > d_.size()) fail(t.begin, "array larger than the file");
        const size_t chars = static_cast<size_t>((hs + n + 2) / 3 * 4);
        if (!base64_decode(src.substr(0, std::min(src.size(), chars)), decoded)) fail(t.content, "bad base64 data");
      }
      src = decoded;
    }
    if (src.size() < hs) fail(t.content, "binary data shorter than its header");
    const uint64_t n = header_value(src.data(), hs);
    if (n > src.size() - hs) fail(t.content, "binary data shorter than its header says");
    bytes.assign(src.data() + hs, static_cast<size_t>(n));
  } else {
    // Header: blocks, block size, last block size, compressed sizes.
    std::string head;
    std::string_view hsrc = src;
    if (base64) {
      if (!base64_decode(src.substr(0, std::min(src.size(), (3 * hs + 2) / 3 * 4)), head)) fail(t.content, "bad base64 data");
      if (head.size() < 3 * hs) fail(t.content, "compressed header too short");
      const uint64_t blocks = header_value(head.data(), hs);
      if (blocks > d_.size()) fail(t.content, "too many compressed blocks");
      const size_t chars = static_cast<size_t>(((3 + blocks) * hs + 2) / 3 * 4);
      if (chars > src.size() || !base64_decode(src.substr(0, chars), head)) fail(t.content, "bad compressed header");
      hsrc = head;
      src = src.substr(chars);
    }
    if (hsrc.size() < 3 * hs) fail(t.content, "compressed header too short");
    const uint64_t blocks = header_value(hsrc.data(), hs);
    const uint64_t block_size = header_value(hsrc.data() + hs, hs);
    const uint64_t last = header_value(hsrc.data() + 2 * hs, hs);
    if (hsrc.size() / hs < 3 + blocks) fail(t.content, "compressed header too short");
    uint64_t total_comp = 0;
    for (uint64_t b = 0; b < blocks; ++b) total_comp += header_value(hsrc.data() + (3 + b) * hs, hs);
    if (!base64) src = src.substr(static_cast<size_t>((3 + blocks) * hs));
    std::string comp;
    if (base64) {
      if (!base64_decode(src.substr(0, std::min<uint64_t>(src.size(), (total_comp + 2) / 3 * 4 + 8)), comp))
        fail(t.content, "bad base64 data");
      src = comp;
    }
    // The sizes come from the file: check them against the expected array
    // before allocating anything.
    const uint64_t want = expected * elem_size;
    if (block_size > want + 1 || last > block_size || blocks > want / (block_size ? block_size : 1) + 1)
      fail(t.content, "compressed block sizes do not match the array");
    const uint64_t total = blocks == 0 ? 0 : (blocks - 1) * block_size + (last ? last : block_size);
    if (total != want) fail(t.content, "compressed array '" + attr(t, "Name", "") + "' has " + std::to_string(total) +
                                           " bytes, expected " + std::to_string(want));
    bytes.resize(static_cast<size_t>(total));
    size_t at = 0, out_at = 0;
    for (uint64_t b = 0; b < blocks; ++b) {
      const uint64_t csize = header_value(hsrc.data() + (3 + b) * hs, hs);
      const uint64_t usize = b + 1 == blocks && last ? last : block_size;
      if (csize > src.size() - at) fail(t.content, "compressed block beyond the data");
      uLongf got = static_cast<uLongf>(usize);
      if (uncompress(reinterpret_cast<Bytef*>(bytes.data() + out_at), &got,
                     reinterpret_cast<const Bytef*>(src.data() + at), static_cast<uLong>(csize)) != Z_OK ||
          got != usize)
        fail(t.content, "bad zlib data");
      at += static_cast<size_t>(csize);
      out_at += static_cast<size_t>(usize);
    }
  }
  if (bytes.size() != expected * elem_size)
    fail(t.content, "array '" + attr(t, "Name", "") + "' has " + std::to_string(bytes.size() / elem_size) +
                        " values, expected " + std::to_string(expected));
  return bytes;
}

template <class T>
std::vector<T> VtuReader::values(const Tag& t, uint64_t expected) {
  const std::string type = attr(t, "type");
  const size_t size = type_size(type);
  if (size == 0) fail(t.begin, "unsupported data type '" + type.substr(0, 40) + "'");
  const std::string format = attr(t, "format", "ascii");
  std::vector<T> out;
  std::string_view text;
  if (format != "appended") {
    const size_t end = d_.find("</DataArray>", t.content);
    if (end == std::string_view::npos) fail(t.begin, "<DataArray> not closed");
    text = d_.substr(t.content, end - t.content);
  }
  if (format == "ascii") {
    Cursor in(text, path_);
    size_t line = 1;
    for (size_t i = 0; i < t.content; ++i) line += d_[i] == '\n';
    out.reserve(detail::capped(expected, text.size(), 2));
    while (!in.at_end()) {
      const std::string_view tok = in.token_in_line();
      double v;
      if (!Cursor::parse_real(tok, v))
        throw InputError(path_ + ":" + std::to_string(line + in.line() - 1) + ": expected a number, found '" +
                         std::string(tok.substr(0, 40)) + "'");
      if constexpr (std::is_integral_v<T>) out.push_back(std::abs(v) < 9e18 ? static_cast<T>(v) : T(-1));
      else out.push_back(static_cast<T>(v));
    }
    if (out.size() != expected)
      fail(t.content, "array '" + attr(t, "Name", "") + "' has " + std::to_string(out.size()) + " values, expected " +
                          std::to_string(expected));
    return out;
  }
  if (format != "binary" && format != "appended") fail(t.begin, "unknown format '" + format.substr(0, 40) + "'");
  const std::string bytes = decoded_bytes(t, text, size, expected);
  out.resize(expected);
  // One loop per stored type: the type is looked up once, not per value.
  auto copy = [&](auto stored) {
    using S = decltype(stored);
    for (size_t i = 0; i < expected; ++i) {
      S v;
      std::memcpy(&v, bytes.data() + i * sizeof(S), sizeof(S));
      if constexpr (std::is_same_v<T, S>) out[i] = v;
      else out[i] = convert<T>(reinterpret_cast<const char*>(&v), type);
    }
  };
  if (type == "Float64") copy(double{});
  else if (type == "Int64") copy(int64_t{});
  else if (type == "Int32") copy(int32_t{});
  else if (type == "UInt8") copy(uint8_t{});
  else for (size_t i = 0; i < expected; ++i) out[i] = convert<T>(bytes.data() + i * size, type);
  return out;
}

Mesh VtuReader::read() {
  // First pass: the file header and where appended data starts.
  Tag t;
  bool is_vtu = false;
  while (next_tag(t)) {
    if (t.name == "VTKFile" && !t.closing) {
      is_vtu = true;
      if (attr(t, "type", "") != "UnstructuredGrid") fail(t.begin, "not an UnstructuredGrid VTK file");
      if (attr(t, "byte_order", "LittleEndian") != "LittleEndian") fail(t.begin, "big-endian VTU is not supported");
      const std::string h = attr(t, "header_type", "UInt32");
      if (h != "UInt32" && h != "UInt64") fail(t.begin, "unsupported header_type " + h.substr(0, 40));
      header_size_ = h == "UInt64" ? 8 : 4;
      const std::string comp = attr(t, "compressor", "");
      if (!comp.empty() && comp != "vtkZLibDataCompressor") fail(t.begin, "unsupported compressor " + comp.substr(0, 40));
      compressed_ = !comp.empty();
    } else if (t.name == "AppendedData" && !t.closing) {
      appended_base64_ = attr(t, "encoding", "raw") == "base64";
      const size_t underscore = d_.find('_', t.content);
      if (underscore == std::string_view::npos) fail(t.begin, "appended data has no '_' marker");
      appended_ = underscore + 1;
      break;  // raw bytes follow: no more tags to scan
    }
  }
  if (!is_vtu) fail(0, "not a VTK XML file (no <VTKFile>)");
  pos_ = 0;
  uint64_t npoints = 0, ncells = 0;
  bool have_piece = false;
  std::vector<Vec3> points;
  detail::VtkCells cells;
  std::vector<int64_t> offsets;
  bool have_types = false, have_offsets = false, have_conn = false, have_points = false;
  Tag conn_tag;
  std::string section;  // Points, Cells, CellData, PointData
  while (next_tag(t)) {
    if (appended_ != std::string_view::npos && t.begin >= appended_) break;
    if (t.name == "Piece" && !t.closing) {
      if (have_piece) fail(t.begin, "only one <Piece> is supported");
      have_piece = true;
      int64_t v;
      if (!Cursor::parse_int(attr(t, "NumberOfPoints"), v) || v < 0) fail(t.begin, "bad NumberOfPoints");
      npoints = static_cast<uint64_t>(v);
      if (!Cursor::parse_int(attr(t, "NumberOfCells"), v) || v < 0) fail(t.begin, "bad NumberOfCells");
      ncells = static_cast<uint64_t>(v);
      if (npoints > d_.size() || ncells > d_.size()) fail(t.begin, "more points or cells than the file can hold");
    } else if (t.name == "Points" || t.name == "Cells" || t.name == "CellData" || t.name == "PointData") {
      section = t.closing || t.self_closing ? "" : t.name;
    } else if (t.name == "DataArray" && !t.closing) {
      if (!have_piece) fail(t.begin, "<DataArray> outside a <Piece>");
      const std::string name = attr(t, "Name", "");
      if (section == "Points") {
        const std::string nc = attr(t, "NumberOfComponents", "1");
        if (nc != "3") fail(t.begin, "points must have 3 components");
        const std::vector<double> xyz = values<double>(t, 3 * npoints);
        points.reserve(npoints);
        for (uint64_t i = 0; i < npoints; ++i) {
          const Vec3 p{xyz[3 * i], xyz[3 * i + 1], xyz[3 * i + 2]};
          if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
            fail(t.begin, "point " + std::to_string(i) + " has a coordinate that is not a finite number");
          points.push_back(p);
        }
        have_points = true;
      } else if (section == "Cells" && name == "types") {
        for (int64_t v : values<int64_t>(t, ncells)) cells.types.push_back(static_cast<int>(v));
        have_types = true;
      } else if (section == "Cells" && name == "offsets") {
        offsets = values<int64_t>(t, ncells);
        have_offsets = true;
      } else if (section == "Cells" && name == "connectivity") {
        conn_tag = t;  // its length is the last offset, which may come later
        have_conn = true;
      } else if (section == "CellData" && attr(t, "NumberOfComponents", "1") == "1") {
        cells.data[name] = values<double>(t, ncells);
      }
    }
  }
  if (!have_piece) fail(0, "no <Piece>");
  if (npoints && !have_points) fail(0, "no points");
  if (ncells && (!have_types || !have_offsets || !have_conn)) fail(0, "cells need types, offsets and connectivity");
  if (have_conn) {
    const int64_t n = offsets.empty() ? 0 : offsets.back();
    if (n < 0 || static_cast<uint64_t>(n) > d_.size()) fail(conn_tag.begin, "bad cell offsets");
    cells.conn = values<int64_t>(conn_tag, static_cast<uint64_t>(n));
    for (int64_t v : cells.conn)
      if (v < 0 || static_cast<uint64_t>(v) >= npoints)
        fail(conn_tag.content, "a cell refers to point " + std::to_string(v) + ", which does not exist (" +
                                   std::to_string(npoints) + " points)");
  }
  cells.offsets.assign(1, 0);
  cells.offsets.insert(cells.offsets.end(), offsets.begin(), offsets.end());
  return detail::mesh_from_vtk(std::move(points), cells, path_);
}

Mesh read_vtu(const std::string& path) {
  const std::string data = detail::load_file(path);
  return VtuReader(data, path).read();
}

}  // namespace

Format make_vtu_format() { return {"vtu", {".vtu"}, true, read_vtu, write_vtu}; }

}  // namespace vd::io
