// VTK XML unstructured grid (.vtu). Writes inline ASCII or base64 binary with
// header_type="UInt64" declared (VTK aborts on an undeclared 64-bit header).
// Reads inline ascii/binary, blocks compressed by zlib, LZ4 or LZMA (VTK's
// three compressors) and raw or base64 appended data, with UInt32 or UInt64
// headers, little- or big-endian, in one piece or several (welded where they
// meet); and a .pvtu by the pieces it lists.
#include <lz4.h>
#include <lzma.h>
#include <zlib.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <map>
#include <optional>
#include <set>
#include <type_traits>

#include "formats.h"
#include "io_util.h"
#include "vtk_common.h"

namespace vd::io {
namespace {

using detail::Cursor;

// ---------------------------------------------------------------------------
// base64

const char kB64[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";

// Two base64 characters for each 12-bit value, in output order.
const std::array<std::array<char, 2>, 4096>& b64_pairs() {
  static const auto table = [] {
    std::array<std::array<char, 2>, 4096> t{};
    for (size_t v = 0; v < t.size(); ++v) t[v] = {kB64[v >> 6], kB64[v & 63]};
    return t;
  }();
  return table;
}

// Appends the base64 of n bytes, written in place, two characters per table
// look-up (appending four characters at a time was a fifth of a binary VTU
// write, one look-up per character half of what was left).
void base64_append(std::string& out, const unsigned char* p, size_t n) {
  const auto& pairs = b64_pairs();
  const size_t at = out.size();
  out.resize(at + (n + 2) / 3 * 4);
  char* o = out.data() + at;
  size_t i = 0;
  for (; i + 3 <= n; i += 3, o += 4) {
    const uint32_t v = (uint32_t{p[i]} << 16) | (uint32_t{p[i + 1]} << 8) | p[i + 2];
    std::memcpy(o, pairs[v >> 12].data(), 2);
    std::memcpy(o + 2, pairs[v & 4095].data(), 2);
  }
  if (i < n) {
    const uint32_t v = (uint32_t{p[i]} << 16) | (i + 1 < n ? uint32_t{p[i + 1]} << 8 : 0);
    o[0] = kB64[v >> 18];
    o[1] = kB64[(v >> 12) & 63];
    o[2] = i + 1 < n ? kB64[(v >> 6) & 63] : '=';
    o[3] = '=';
  }
}

// Decodes base64 a piece at a time, skipping white space. Padding ends a
// group, so separately encoded header and data (as VTK writes compressed
// arrays) decode as one stream.
class Base64Reader {
 public:
  explicit Base64Reader(std::string_view in)
      : begin_(reinterpret_cast<const unsigned char*>(in.data())), p_(begin_), end_(p_ + in.size()) {}
  // Up to `cap` bytes into `out`; false on a bad character.
  bool read(char* out, size_t cap, size_t& got);
  size_t consumed() const { return static_cast<size_t>(p_ - begin_); }
  // The character a failed read() stopped at.
  char last() const { return p_ > begin_ ? static_cast<char>(p_[-1]) : 0; }

 private:
  const unsigned char* begin_;
  const unsigned char* p_;
  const unsigned char* end_;
  uint32_t acc_ = 0;
  int bits_ = 0;
};

bool Base64Reader::read(char* out, size_t cap, size_t& got) {
  static const std::array<int8_t, 256> table = [] {
    std::array<int8_t, 256> t;
    t.fill(-1);
    for (int i = 0; i < 64; ++i) t[static_cast<unsigned char>(kB64[i])] = static_cast<int8_t>(i);
    t[' '] = t['\n'] = t['\r'] = t['\t'] = -2;
    t['='] = -3;
    return t;
  }();
  // Each character's six bits already in place for its position in a
  // group of four; bit 31 marks anything else, which takes the slow path.
  struct Shifted {
    uint32_t at[4][256];
  };
  static const Shifted shifted = [] {
    Shifted t;
    for (int k = 0; k < 4; ++k)
      for (int c = 0; c < 256; ++c)
        t.at[k][c] = table[static_cast<size_t>(c)] >= 0 ? uint32_t(table[static_cast<size_t>(c)]) << (18 - 6 * k)
                                                        : 0x80000000u;
    return t;
  }();
  char* o = out;
  char* const o_end = out + cap;
  while (p_ < end_ && o < o_end) {
    // Four characters at a time while they are all data, else one by one.
    if (bits_ == 0) {
      while (end_ - p_ >= 4 && o_end - o >= 3) {
        const uint32_t v = shifted.at[0][p_[0]] | shifted.at[1][p_[1]] | shifted.at[2][p_[2]] | shifted.at[3][p_[3]];
        if (v & 0x80000000u) break;
        o[0] = static_cast<char>(v >> 16);
        o[1] = static_cast<char>((v >> 8) & 0xFF);
        o[2] = static_cast<char>(v & 0xFF);
        o += 3;
        p_ += 4;
      }
      if (p_ >= end_ || o >= o_end) break;
    }
    const int v = table[*p_++];
    if (v == -2) continue;
    if (v == -3) {
      bits_ = 0;  // the group's leftover bits are padding
      acc_ = 0;
      continue;
    }
    if (v < 0) return false;
    acc_ = ((acc_ << 6) | static_cast<uint32_t>(v)) & 0xFFFFFF;
    bits_ += 6;
    if (bits_ >= 8) {
      bits_ -= 8;
      *o++ = static_cast<char>((acc_ >> bits_) & 0xFF);
    }
  }
  got = static_cast<size_t>(o - out);
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
         "  <UnstructuredGrid>\n";
  // Region and face names in the data set's field data (vtk_common.h).
  const std::string names = detail::vtk_names_text(m);
  if (!names.empty()) {
    out << "    <FieldData>\n      <DataArray type=\"UInt8\" Name=\"" << detail::kVtkNamesArray << "\" NumberOfTuples=\""
        << names.size() << "\" format=\"ascii\">\n";
    detail::write_text_values(out, names.size(), 12, [&](size_t i) { return static_cast<int>(static_cast<unsigned char>(names[i])); });
    out << "      </DataArray>\n    </FieldData>\n";
  }
  out << "    <Piece NumberOfPoints=\"" << m.points.size() << "\" NumberOfCells=\"" << ncells << "\">\n";
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
      std::vector<unsigned char> piece(kPiece + 16);
      size_t fill = 0;
      auto put = [&](const void* p, size_t size) {
        std::memcpy(piece.data() + fill, p, size);
        fill += size;
        if (fill < kPiece) return;
        const size_t whole = fill / 3 * 3;
        base64_append(out.str(), piece.data(), whole);
        std::memmove(piece.data(), piece.data() + whole, fill - whole);
        fill -= whole;
        out.spill_if_full();
      };
      const uint64_t bytes = n * sizeof(T);
      out << "          ";
      put(&bytes, sizeof bytes);
      for (size_t i = 0; i < n; ++i) {
        const T v = value(i);
        put(&v, sizeof v);
      }
      base64_append(out.str(), piece.data(), fill);
      out << '\n';
    } else {
      detail::write_text_values(out, n, 12, value);
    }
    out << "        </DataArray>\n";
  };
  out << "      <Points>\n";
  array("Float64", "Points", 3, 3 * m.points.size(),
        [&](size_t i) { return m.points[i / 3][static_cast<int>(i % 3)]; });
  out << "      </Points>\n      <Cells>\n";
  // Int32 when every value fits (VTK reads either): a third of a binary
  // file's bytes and of its writing time went into the upper halves of Int64
  // node numbers and offsets.
  if (m.points.size() <= size_t{INT32_MAX} && c.connectivity_size() <= size_t{INT32_MAX}) {
    array("Int32", "connectivity", 1, c.connectivity_size(), [&](size_t i) { return static_cast<int32_t>(c.flat_node(i)); });
    array("Int32", "offsets", 1, ncells, [&](size_t i) { return static_cast<int32_t>(c.end(i)); });
  } else {
    array("Int64", "connectivity", 1, c.connectivity_size(), [&](size_t i) { return int64_t{c.flat_node(i)}; });
    array("Int64", "offsets", 1, ncells, [&](size_t i) { return c.end(i); });
  }
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

// A DataArray's stored type, looked up once per array (comparing the type
// name per value was a third of a 1M-tetrahedron read).
using Stored = detail::ValueType;

Stored stored_type(const std::string& type) {
  static const std::pair<const char*, Stored> names[] = {
      {"Int8", Stored::Int8},     {"UInt8", Stored::UInt8},     {"Int16", Stored::Int16},
      {"UInt16", Stored::UInt16}, {"Int32", Stored::Int32},     {"UInt32", Stored::UInt32},
      {"Int64", Stored::Int64},   {"UInt64", Stored::UInt64},   {"Float32", Stored::Float32},
      {"Float64", Stored::Float64}};
  for (const auto& [name, t] : names)
    if (type == name) return t;
  return Stored::Unknown;
}

// A value of the file's byte order as this machine's (little-endian).
template <class T>
T load_bytes(const char* p, bool swap) {
  T v;
  if (!swap) {
    std::memcpy(&v, p, sizeof v);
  } else {
    char b[sizeof(T)];
    for (size_t i = 0; i < sizeof(T); ++i) b[i] = p[sizeof(T) - 1 - i];
    std::memcpy(&v, b, sizeof v);
  }
  return v;
}

// One stored value as a double (integers beyond 2^53 lose digits, which no
// index or tag in a mesh file reaches).
double load_value(const char* p, Stored t, bool swap) {
  auto load = [p, swap](auto v) { return static_cast<double>(load_bytes<decltype(v)>(p, swap)); };
  switch (t) {
    case Stored::Int8: return load(int8_t{});
    case Stored::UInt8: return load(uint8_t{});
    case Stored::Int16: return load(int16_t{});
    case Stored::UInt16: return load(uint16_t{});
    case Stored::Int32: return load(int32_t{});
    case Stored::UInt32: return load(uint32_t{});
    case Stored::Int64: return load(int64_t{});
    case Stored::UInt64: return load(uint64_t{});
    case Stored::Float32: return load(float{});
    default: return load(double{});
  }
}

uint64_t header_value(const char* p, size_t size, bool swap) {
  return size == 8 ? load_bytes<uint64_t>(p, swap) : load_bytes<uint32_t>(p, swap);
}

enum class Compressor { none, zlib, lz4, lzma };

// One compressed block into `out` (its size known from the header): true
// when it decodes to exactly that many bytes.
bool decompress_block(Compressor c, const char* in, size_t in_size, char* out, size_t out_size) {
  switch (c) {
    case Compressor::zlib: {
      uLongf got = static_cast<uLongf>(out_size);
      return uncompress(reinterpret_cast<Bytef*>(out), &got, reinterpret_cast<const Bytef*>(in),
                        static_cast<uLong>(in_size)) == Z_OK &&
             got == out_size;
    }
    case Compressor::lz4:
      // vtkLZ4DataCompressor writes raw LZ4 blocks.
      if (in_size > INT32_MAX || out_size > INT32_MAX) return false;
      return LZ4_decompress_safe(in, out, static_cast<int>(in_size), static_cast<int>(out_size)) ==
             static_cast<int>(out_size);
    case Compressor::lzma: {
      // vtkLZMADataCompressor (and meshio's "lzma") write .xz streams. The
      // decoder's memory is bounded: a stream's header may ask for a 4 GiB
      // dictionary, and VTK's presets need under 100 MiB.
      uint64_t memlimit = uint64_t{256} << 20;
      size_t in_pos = 0, out_pos = 0;
      return lzma_stream_buffer_decode(&memlimit, 0, nullptr, reinterpret_cast<const uint8_t*>(in), &in_pos,
                                       in_size, reinterpret_cast<uint8_t*>(out), &out_pos, out_size) == LZMA_OK &&
             out_pos == out_size;
    }
    default: return false;
  }
}

const char* compressor_name(Compressor c) {
  return c == Compressor::lz4 ? "LZ4" : c == Compressor::lzma ? "LZMA" : "zlib";
}

// Node counts of the VTK cell types with a fixed count; 0 for types whose
// count varies (poly-vertex, poly-line, polygon, strip, polyhedron...).
int fixed_nodes(int type) {
  static const int table[] = {0, 1, 0, 2, 0, 3, 0, 0, 4, 4, 4, 8, 8, 6, 5, 10, 12, 0, 0, 0, 0,
                              3, 6, 8, 10, 20, 15, 13, 9, 27, 6};
  return type >= 0 && type < static_cast<int>(sizeof table / sizeof table[0]) ? table[type] : 0;
}

// Reads the one <Piece> of an UnstructuredGrid straight into a Mesh: arrays
// are located first, then decoded in the order the mesh needs them (types,
// offsets, connectivity, cell data) a piece at a time, and the file's pages
// are let go behind each array. Holding the file, every decoded array and
// its converted copy peaked at 8.8 times the mesh on 1M tetrahedra.
class VtuReader {
 public:
  VtuReader(const detail::FileBytes& file, const std::string& path) : file_(file), d_(file.view()), path_(path) {}
  Mesh read();

 private:
  [[noreturn]] void fail(size_t offset, const std::string& what) const {
    size_t line = 1;
    for (size_t i = 0; i < offset && i < d_.size(); ++i) line += d_[i] == '\n';
    throw InputError(path_ + ":" + std::to_string(line) + ": " + what);
  }
  bool next_tag(Tag& t);
  // d_.find(what, from), a few MiB at a time, letting the pages it passed go.
  size_t find_letting_go(std::string_view what, size_t from) const {
    constexpr size_t kWindow = size_t{4} << 20;
    for (size_t at = from; at < d_.size(); at += kWindow) {
      const size_t end = std::min(d_.size(), at + kWindow + what.size() - 1);
      const size_t hit = d_.substr(0, end).find(what, at);
      if (hit != std::string_view::npos) return hit;
      file_.drop(at, at + kWindow);
    }
    return std::string_view::npos;
  }
  std::string attr(const Tag& t, const char* name, const char* fallback = nullptr) const;
  // Calls store(i, value) for the `expected` values of one DataArray, in order.
  template <class Store>
  void each_value(const Tag& t, uint64_t expected, Store store);
  // Calls feed(bytes, n) with the payload of a binary array, piece by piece.
  template <class Feed>
  void each_piece(const Tag& t, std::string_view text, uint64_t want, size_t value_size, Feed feed);
  void read_cells(const Tag& types, const Tag& offsets, const Tag& conn, uint64_t ncells);
  void read_cell_data(const std::map<std::string, Tag>& arrays, uint64_t ncells);

  const detail::FileBytes& file_;
  std::string_view d_;
  std::string path_;
  size_t pos_ = 0;
  size_t header_size_ = 4;  // UInt32 unless declared
  Compressor compressor_ = Compressor::none;
  bool swap_ = false;       // byte_order="BigEndian" (VTK writes it on request)
  size_t appended_ = std::string_view::npos;  // offset after '_'
  bool appended_base64_ = false;
  Mesh m_;
  std::vector<uint8_t> types_;  // per cell; 255 for types beyond 254
  std::optional<Tag> names_;    // the data set's detail::kVtkNamesArray
};

bool VtuReader::next_tag(Tag& t) {
  for (;;) {
    const size_t lt = d_.find('<', pos_);
    // Array text between tags is decoded later: let its pages go now, or
    // scanning alone would bring the whole file into memory.
    if (lt - pos_ > (size_t{1} << 20)) file_.drop(pos_, lt == std::string_view::npos ? d_.size() : lt);
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

template <class Feed>
void VtuReader::each_piece(const Tag& t, std::string_view text, uint64_t want, size_t value_size, Feed feed) {
  constexpr size_t kPiece = 3 * 16384;  // bytes decoded at a time
  const size_t hs = header_size_;
  const std::string format = attr(t, "format");
  const bool base64 = format == "binary" || (format == "appended" && appended_base64_);
  std::string_view src = text;
  if (format == "appended") {
    const uint64_t offset = std::strtoull(attr(t, "offset").c_str(), nullptr, 10);
    if (appended_ == std::string_view::npos || offset > d_.size() - appended_) fail(t.begin, "bad appended data offset");
    src = d_.substr(appended_ + static_cast<size_t>(offset));
  }
  // Base64 text is measured in characters below: start at the first one
  // (raw appended bytes are taken as they are).
  if (base64)
    while (!src.empty() && std::isspace(static_cast<unsigned char>(src.front()))) src.remove_prefix(1);
  const size_t src_at = static_cast<size_t>(src.data() - d_.data());
  auto count_error = [&](uint64_t bytes) {
    fail(t.content, "array '" + attr(t, "Name", "") + "' has " + std::to_string(bytes / value_size) +
                        " values, expected " + std::to_string(want / value_size));
  };
  if (compressor_ == Compressor::none) {
    if (!base64) {
      if (src.size() < hs) fail(t.content, "binary data shorter than its header");
      const uint64_t n = header_value(src.data(), hs, swap_);
      if (n > src.size() - hs) fail(t.content, "binary data shorter than its header says");
      if (n != want) count_error(n);
      for (uint64_t at = 0; at < n; at += kPiece) {
        const size_t step = static_cast<size_t>(std::min<uint64_t>(kPiece, n - at));
        feed(src.data() + hs + at, step);
        if ((at / kPiece) % 64 == 63) file_.drop(src_at, src_at + hs + at);
      }
      file_.drop(src_at, src_at + hs + n);
      return;
    }
    Base64Reader in(src);
    char head[8];
    size_t got = 0;
    if (!in.read(head, hs, got)) fail(t.content, "bad base64 data");
    if (got < hs) fail(t.content, "binary data shorter than its header");
    const uint64_t n = header_value(head, hs, swap_);
    if (n != want) {
      if (n > src.size()) fail(t.content, "binary data shorter than its header says");
      count_error(n);
    }
    std::vector<char> piece(kPiece);
    uint64_t done = 0;
    while (done < n) {
      if (!in.read(piece.data(), static_cast<size_t>(std::min<uint64_t>(kPiece, n - done)), got))
        fail(t.content, in.last() == '<' ? "binary data shorter than its header says" : "bad base64 data");
      if (got == 0) fail(t.content, "binary data shorter than its header says");
      feed(piece.data(), got);
      done += got;
      if ((done / kPiece) % 64 == 63) file_.drop(src_at, src_at + in.consumed());
    }
    file_.drop(src_at, src_at + in.consumed());
    return;
  }
  // Header: blocks, block size, last block size, compressed sizes; base64
  // in one stream with the data, or encoded apart (padding ends a group).
  std::string head, comp;
  std::string_view hsrc = src;
  Base64Reader in(src);
  auto decode = [&](std::string& out, uint64_t n, const char* what) {
    if (n > src.size()) fail(t.content, std::string(what) + " larger than the file");
    const size_t old = out.size();
    out.resize(old + static_cast<size_t>(n));
    size_t got = 0;
    if (!in.read(out.data() + old, static_cast<size_t>(n), got)) fail(t.content, "bad base64 data");
    if (got != n) fail(t.content, std::string(what) + " shorter than its header says");
  };
  if (base64) {
    decode(head, 3 * hs, "compressed header");
    decode(head, header_value(head.data(), hs, swap_) * hs, "compressed header");
    hsrc = head;
  }
  if (hsrc.size() < 3 * hs) fail(t.content, "compressed header too short");
  const uint64_t blocks = header_value(hsrc.data(), hs, swap_);
  const uint64_t block_size = header_value(hsrc.data() + hs, hs, swap_);
  const uint64_t last = header_value(hsrc.data() + 2 * hs, hs, swap_);
  if (blocks > hsrc.size() || hsrc.size() / hs < 3 + blocks) fail(t.content, "compressed header too short");
  uint64_t total_comp = 0;
  for (uint64_t b = 0; b < blocks; ++b) total_comp += header_value(hsrc.data() + (3 + b) * hs, hs, swap_);
  if (base64) {
    decode(comp, total_comp, "compressed data");
    src = comp;
  } else {
    src = src.substr(static_cast<size_t>((3 + blocks) * hs));
  }
  // The sizes come from the file: check them against the expected array
  // before allocating anything.
  // One block may be declared larger than the array: VTK and meshio write
  // their block size (32768) whatever the array's, and the last block's
  // size says what it holds (a 4-point file was refused until 2026-11-29).
  if (last > block_size || (blocks > 1 && block_size > want) || blocks > want / (block_size ? block_size : 1) + 1)
    fail(t.content, "compressed block sizes do not match the array");
  const uint64_t total = blocks == 0 ? 0 : (blocks - 1) * block_size + (last ? last : block_size);
  if (total != want) count_error(total);
  std::vector<char> block(static_cast<size_t>(std::min(block_size, want)));
  size_t at = 0;
  for (uint64_t b = 0; b < blocks; ++b) {
    const uint64_t csize = header_value(hsrc.data() + (3 + b) * hs, hs, swap_);
    const uint64_t usize = b + 1 == blocks && last ? last : block_size;
    if (csize > src.size() - at) fail(t.content, "compressed block beyond the data");
    if (!decompress_block(compressor_, src.data() + at, static_cast<size_t>(csize), block.data(),
                          static_cast<size_t>(usize)))
      fail(t.content, std::string("bad ") + compressor_name(compressor_) + " data");
    feed(block.data(), static_cast<size_t>(usize));
    at += static_cast<size_t>(csize);
  }
}

template <class Store>
void VtuReader::each_value(const Tag& t, uint64_t expected, Store store) {
  const std::string type = attr(t, "type");
  const Stored stored = stored_type(type);
  const size_t size = detail::value_size(stored);
  if (size == 0) fail(t.begin, "unsupported data type '" + type.substr(0, 40) + "'");
  const std::string format = attr(t, "format", "ascii");
  std::string_view text;
  if (format == "binary") {
    // The header says where the data ends: '<' after it is the closing tag.
    text = d_.substr(t.content);
  } else if (format != "appended") {
    // The numbers end at the first tag: </DataArray>, or an element VTK
    // puts after them (<InformationKey name="L2_NORM_RANGE">, in every
    // ASCII file of vtkXMLUnstructuredGridWriter).
    const size_t end = find_letting_go("<", t.content);
    if (end == std::string_view::npos) fail(t.begin, "<DataArray> not closed");
    text = d_.substr(t.content, end - t.content);
  }
  auto count_error = [&](uint64_t found) {
    fail(t.content, "array '" + attr(t, "Name", "") + "' has " + std::to_string(found) + " values, expected " +
                        std::to_string(expected));
  };
  if (format == "ascii") {
    Cursor in(text, path_);
    uint64_t i = 0;
    // The text is parsed where it lies in the file: let its pages go behind.
    const size_t at = static_cast<size_t>(text.data() - d_.data());
    file_.drop(at, at + text.size());
    size_t next_drop = size_t{1} << 20;
    while (!in.at_end()) {
      if (in.pos() >= next_drop) {
        file_.drop(at, at + in.pos());
        next_drop = in.pos() + (size_t{1} << 20);
      }
      const std::string_view tok = in.token_in_line();
      double v;
      if (!Cursor::parse_real(tok, v)) {
        // Counted only now: counting lines up to every array faulted the
        // whole file back in.
        size_t line = 1;
        for (size_t k = 0; k < t.content; ++k) line += d_[k] == '\n';
        throw InputError(path_ + ":" + std::to_string(line + in.line() - 1) + ": expected a number, found '" +
                         std::string(tok.substr(0, 40)) + "'");
      }
      if (i == expected) count_error(i + 1);
      store(i++, v);
    }
    if (i != expected) count_error(i);
    return;
  }
  if (format != "binary" && format != "appended") fail(t.begin, "unknown format '" + format.substr(0, 40) + "'");
  if (expected > d_.size()) count_error(expected);
  // A value may straddle two pieces: its first bytes wait in `carry`.
  char carry[8];
  size_t carried = 0;
  uint64_t i = 0;
  each_piece(t, text, expected * size, size, [&](const char* p, size_t n) {
    while (carried && carried < sizeof carry && n) {
      carry[carried++] = *p++;
      --n;
      if (carried == size) {
        store(i++, load_value(carry, stored, swap_));
        carried = 0;
      }
    }
    for (; n >= size; p += size, n -= size) store(i++, load_value(p, stored, swap_));
    std::memcpy(carry, p, n);
    carried = n;
  });
}

// Cells: types first (a byte each), then offsets checked against the fixed
// node counts (only cells of varying size keep theirs), then connectivity
// straight into the tetrahedra and triangles.
void VtuReader::read_cells(const Tag& types, const Tag& offsets, const Tag& conn, uint64_t ncells) {
  types_.assign(static_cast<size_t>(ncells), 0);
  each_value(types, ncells, [&](uint64_t i, double v) {
    types_[i] = v >= 0 && v < 255 ? static_cast<uint8_t>(v) : uint8_t{255};
  });
  std::map<uint64_t, int64_t> varying;  // cell -> node count, for cells of varying size
  int64_t previous = 0;
  each_value(offsets, ncells, [&](uint64_t i, double v) {
    const int64_t end = std::abs(v) < 9e18 ? static_cast<int64_t>(v) : -1;
    const int64_t count = end - previous;
    const int fixed = fixed_nodes(types_[i]);
    if (count < 0 || end > static_cast<int64_t>(d_.size()) || (fixed && count != fixed))
      fail(offsets.content, "cell " + std::to_string(i) + " of type " + std::to_string(types_[i]) +
                                " has offsets for " + std::to_string(count) + " nodes" +
                                (fixed ? ", not " + std::to_string(fixed) : std::string()));
    if (!fixed) varying[i] = count;
    previous = end;
  });
  const detail::VtkElementCounts counts(types_);
  if (counts.mixed_order()) fail(types.content, "first- and second-order cells of one kind are mixed");
  if (counts.first_lost >= 0) fail(types.content, counts.lost_text(types_));
  m_.tets.resize(counts.tets);
  m_.tet_mid.resize(counts.tets10);
  m_.triangles.resize(counts.tris);
  m_.triangle_mid.resize(counts.tris6);
  const int np = static_cast<int>(m_.points.size());
  // The cell the next connectivity value belongs to, and where in it.
  uint64_t cell = 0;
  int64_t k = 0, j = 0;
  size_t tet = 0, tri = 0;
  auto size_of = [&](uint64_t c) {
    const int fixed = fixed_nodes(types_[c]);
    return fixed ? int64_t{fixed} : varying[c];
  };
  auto start_cell = [&] {
    while (cell < ncells && (k = size_of(cell)) == 0) ++cell;
    j = 0;
  };
  start_cell();
  each_value(conn, static_cast<uint64_t>(previous), [&](uint64_t, double v) {
    if (!(v >= 0 && v < np))
      fail(conn.content, "a cell refers to point " + std::to_string(static_cast<long long>(std::abs(v) < 9e18 ? v : -1)) +
                             ", which does not exist (" + std::to_string(np) + " points)");
    const int n = static_cast<int>(v);
    const int type = types_[cell];
    if (detail::vtk_is_tet(type)) {
      if (j < 4) m_.tets[tet].v[static_cast<size_t>(j)] = n;
      else m_.tet_mid[tet][static_cast<size_t>(j - 4)] = n;
    } else if (detail::vtk_is_triangle(type)) {
      if (j < 3) m_.triangles[tri].v[static_cast<size_t>(j)] = n;
      else m_.triangle_mid[tri][static_cast<size_t>(j - 3)] = n;
    }
    if (++j == k) {
      tet += detail::vtk_is_tet(type);
      tri += detail::vtk_is_triangle(type);
      ++cell;
      start_cell();
    }
  });
}

// The cell data vdmesh uses: region and face (else a tag array other
// programs write), front and back; tetrahedra take the region, triangles
// the rest.
void VtuReader::read_cell_data(const std::map<std::string, Tag>& arrays, uint64_t ncells) {
  auto find = [&](std::initializer_list<const char*> names) -> const Tag* {
    for (const char* n : names) {
      auto it = arrays.find(n);
      if (it != arrays.end()) return &it->second;
    }
    return nullptr;
  };
  const Tag* tags = nullptr;
  for (const char* name : detail::kVtkTagArrays)
    if (!tags) tags = find({name});
  const Tag* region = find({"region"});
  const Tag* face = find({"face"});
  if (!region) region = tags;
  if (!face) face = tags;
  // One pass per array, whatever it sets (a tag array may set region and face).
  std::map<const Tag*, detail::VtkCellRoles> roles;
  if (region) roles[region].region = true;
  if (face) roles[face].face = true;
  if (const Tag* front = find({"front"})) roles[front].front = true;
  if (const Tag* back = find({"back"})) roles[back].back = true;
  for (const auto& [array, r] : roles) {
    detail::VtkCellDataSink sink(m_, r);
    each_value(*array, ncells, [&](uint64_t i, double v) { sink.put(types_[i], v); });
  }
}

// The arrays of one <Piece>, located by the scan of the tags.
struct PieceArrays {
  uint64_t npoints = 0, ncells = 0;
  std::optional<Tag> points, types, offsets, conn;
  std::map<std::string, Tag> cell_data;
};

// `part`'s elements after `whole`'s, its point numbers shifted past whole's.
void append_piece(Mesh& whole, Mesh&& part) {
  const int shift = static_cast<int>(whole.points.size());
  whole.points.insert(whole.points.end(), part.points.begin(), part.points.end());
  auto shifted = [shift](auto& to, const auto& from, auto nodes) {
    for (auto x : from) {
      for (int& v : nodes(x)) v += shift;
      to.push_back(x);
    }
  };
  auto corners = [](auto& element) -> auto& { return element.v; };
  auto itself = [](auto& nodes) -> auto& { return nodes; };
  shifted(whole.tets, part.tets, corners);
  shifted(whole.tet_mid, part.tet_mid, itself);
  shifted(whole.triangles, part.triangles, corners);
  shifted(whole.triangle_mid, part.triangle_mid, itself);
  // Each piece of VTK's parallel writer repeats the data set's names (a
  // .pvtu of a CAD mesh came back with Region1 for Solid1); the first wins.
  whole.region_names.merge(part.region_names);
  whole.face_names.merge(part.face_names);
}

// Elements whose corners another one before them has, dropped (their
// mid-edge nodes with them).
template <class Element, class Mid>
void drop_repeated(std::vector<Element>& elements, std::vector<Mid>& mids) {
  std::set<decltype(Element::v)> seen;
  detail::keep_elements_if(elements, mids, [&seen](const Element& e) {
    auto key = e.v;
    std::sort(key.begin(), key.end());
    return seen.insert(key).second;
  });
}

// Pieces of one data set (VTK's writer with several pieces, or a .pvtu's
// files) repeat the points where they meet: a point at the very
// coordinates of a point of an earlier piece is made that point (else a
// deck written from them falls apart along the cuts) and dropped. Points
// repeated within one piece stay apart, as in a file of one piece (the two
// sides of a crack). Pieces with ghost cells (a ghost level), or each
// holding the whole grid (VTK's writer asked for pieces of a grid with no
// pipeline to split it), repeat cells too: those are dropped once the
// points are one (the 3-piece file of a 576-cell grid read as 1,728).
void weld_pieces(Mesh& m, const std::vector<int>& piece_of) {
  struct Seen {
    int point, piece;
  };
  std::map<std::array<double, 3>, Seen> first;
  std::vector<int> to(m.points.size());
  std::vector<char> kept(m.points.size(), 1);
  for (size_t i = 0; i < m.points.size(); ++i) {
    to[i] = static_cast<int>(i);
    const std::array<double, 3> key{m.points[i].x, m.points[i].y, m.points[i].z};
    const auto [it, fresh] = first.emplace(key, Seen{static_cast<int>(i), piece_of[i]});
    if (!fresh && it->second.piece != piece_of[i]) to[i] = it->second.point, kept[i] = 0;
  }
  // Kept points numbered anew, in order; a welded one takes its first's number.
  std::vector<int> number(m.points.size());
  size_t next = 0;
  for (size_t i = 0; i < m.points.size(); ++i)
    if (kept[i]) m.points[next] = m.points[i], number[i] = static_cast<int>(next++);
  m.points.resize(next);
  auto renumber = [&](int& v) { v = number[static_cast<size_t>(to[static_cast<size_t>(v)])]; };
  for (Tetrahedron& t : m.tets)
    for (int& v : t.v) renumber(v);
  for (TetMidNodes& x : m.tet_mid)
    for (int& v : x) renumber(v);
  for (Triangle& t : m.triangles)
    for (int& v : t.v) renumber(v);
  for (TriMidNodes& x : m.triangle_mid)
    for (int& v : x) renumber(v);
  drop_repeated(m.tets, m.tet_mid);
  drop_repeated(m.triangles, m.triangle_mid);
}

Mesh VtuReader::read() {
  // One pass over the tags: the header, where each array is, and where
  // appended data starts; the arrays are decoded after it.
  Tag t;
  bool is_vtu = false;
  std::vector<PieceArrays> pieces;
  std::string section;  // Points, Cells, CellData, PointData, FieldData
  while (next_tag(t)) {
    if (t.name == "VTKFile" && !t.closing) {
      is_vtu = true;
      if (attr(t, "type", "") != "UnstructuredGrid") fail(t.begin, "not an UnstructuredGrid VTK file");
      const std::string order = attr(t, "byte_order", "LittleEndian");
      if (order != "LittleEndian" && order != "BigEndian") fail(t.begin, "unknown byte_order " + order.substr(0, 40));
      swap_ = order == "BigEndian";
      const std::string h = attr(t, "header_type", "UInt32");
      if (h != "UInt32" && h != "UInt64") fail(t.begin, "unsupported header_type " + h.substr(0, 40));
      header_size_ = h == "UInt64" ? 8 : 4;
      const std::string comp = attr(t, "compressor", "");
      if (comp.empty()) compressor_ = Compressor::none;
      else if (comp == "vtkZLibDataCompressor") compressor_ = Compressor::zlib;
      else if (comp == "vtkLZ4DataCompressor") compressor_ = Compressor::lz4;
      else if (comp == "vtkLZMADataCompressor") compressor_ = Compressor::lzma;
      else fail(t.begin, "unsupported compressor " + comp.substr(0, 40));
    } else if (t.name == "AppendedData" && !t.closing) {
      appended_base64_ = attr(t, "encoding", "raw") == "base64";
      const size_t underscore = d_.find('_', t.content);
      if (underscore == std::string_view::npos) fail(t.begin, "appended data has no '_' marker");
      appended_ = underscore + 1;
      break;  // raw bytes follow: no more tags to scan
    } else if (!is_vtu) {
      continue;
    } else if (t.name == "Piece" && !t.closing) {
      PieceArrays& piece = pieces.emplace_back();
      int64_t v;
      if (!Cursor::parse_int(attr(t, "NumberOfPoints"), v) || v < 0) fail(t.begin, "bad NumberOfPoints");
      piece.npoints = static_cast<uint64_t>(v);
      if (!Cursor::parse_int(attr(t, "NumberOfCells"), v) || v < 0) fail(t.begin, "bad NumberOfCells");
      piece.ncells = static_cast<uint64_t>(v);
      if (piece.npoints > d_.size() || piece.ncells > d_.size()) fail(t.begin, "more points or cells than the file can hold");
    } else if (t.name == "Points" || t.name == "Cells" || t.name == "CellData" || t.name == "PointData" ||
               t.name == "FieldData") {
      section = t.closing || t.self_closing ? "" : t.name;
    } else if (t.name == "DataArray" && !t.closing) {
      // Arrays of the whole data set (VTK writes a time value there, and
      // ParaView more): nothing vdmesh keeps. Refused as "<DataArray>
      // outside a <Piece>" until 2026-11-30.
      if (section == "FieldData") {
        if (attr(t, "Name", "") == detail::kVtkNamesArray) names_ = t;
        continue;
      }
      if (pieces.empty()) fail(t.begin, "<DataArray> outside a <Piece>");
      PieceArrays& piece = pieces.back();
      const std::string name = attr(t, "Name", "");
      if (section == "Points") {
        if (attr(t, "NumberOfComponents", "1") != "3") fail(t.begin, "points must have 3 components");
        piece.points = t;
      } else if (section == "Cells" && name == "types") {
        piece.types = t;
      } else if (section == "Cells" && name == "offsets") {
        piece.offsets = t;
      } else if (section == "Cells" && name == "connectivity") {
        piece.conn = t;
      } else if (section == "CellData" && attr(t, "NumberOfComponents", "1") == "1") {
        piece.cell_data[name] = t;
      }
    }
  }
  if (!is_vtu) fail(0, "not a VTK XML file (no <VTKFile>)");
  if (pieces.empty()) fail(0, "no <Piece>");
  Mesh whole;
  std::vector<int> piece_of;  // each point's piece, when there are several
  for (const PieceArrays& piece : pieces) {
    if (piece.npoints && !piece.points) fail(0, "no points");
    if (piece.ncells && (!piece.types || !piece.offsets || !piece.conn))
      fail(0, "cells need types, offsets and connectivity");
    m_ = Mesh{};
    types_.clear();
    if (piece.points) {
      m_.points.resize(static_cast<size_t>(piece.npoints));
      each_value(*piece.points, 3 * piece.npoints, [&](uint64_t i, double v) {
        if (!std::isfinite(v))
          fail(piece.points->begin, "point " + std::to_string(i / 3) + " has a coordinate that is not a finite number");
        m_.points[i / 3][static_cast<int>(i % 3)] = v;
      });
    }
    if (piece.ncells) {
      read_cells(*piece.types, *piece.offsets, *piece.conn, piece.ncells);
      read_cell_data(piece.cell_data, piece.ncells);
    }
    if (pieces.size() == 1) {
      whole = std::move(m_);
    } else {
      detail::require_valid(m_, path_);
      piece_of.resize(whole.points.size() + m_.points.size(), static_cast<int>(&piece - pieces.data()));
      append_piece(whole, std::move(m_));
    }
  }
  if (pieces.size() > 1) weld_pieces(whole, piece_of);
  if (names_) {
    int64_t n = 0;
    if (!Cursor::parse_int(attr(*names_, "NumberOfTuples", "0"), n) || n < 0 || static_cast<uint64_t>(n) > d_.size())
      fail(names_->begin, "bad NumberOfTuples");
    std::string text(static_cast<size_t>(n), '\0');
    each_value(*names_, static_cast<uint64_t>(n), [&](uint64_t i, double v) {
      if (!(v >= 0 && v <= 255)) fail(names_->begin, "a byte of the names out of range");
      text[i] = static_cast<char>(static_cast<unsigned char>(v));
    });
    detail::read_vtk_names_text(text, whole);
  }
  return whole;
}

// The points and elements of a .vtu (its pieces welded), its triangles'
// sides not yet known.
Mesh read_vtu_elements(const std::string& path) {
  const detail::FileBytes file(path);
  return VtuReader(file, path).read();
}

Mesh read_vtu(const std::string& path) {
  Mesh m = read_vtu_elements(path);
  detail::require_valid(m, path);
  detail::sides_from_tets(m);
  return m;
}

// A parallel unstructured grid (.pvtu, ParaView's and VTK's parallel
// writers): the .vtu files its <Piece Source="..."/> lines name, relative
// to its folder, read in turn and welded into one mesh.
Mesh read_pvtu(const std::string& path) {
  const detail::FileBytes file(path);
  const std::string_view d = file.view();
  auto line_of = [d](size_t at) { return 1 + std::count(d.begin(), d.begin() + static_cast<std::ptrdiff_t>(at), '\n'); };
  if (d.find("PUnstructuredGrid") == std::string_view::npos)
    throw InputError(path + ": not a parallel unstructured grid (no PUnstructuredGrid)");
  const std::filesystem::path folder = std::filesystem::path(path).parent_path();
  Mesh whole;
  std::vector<int> piece_of;  // each point's file
  size_t pieces = 0;
  for (size_t at = d.find("<Piece"); at != std::string_view::npos; at = d.find("<Piece", at + 1)) {
    const size_t end = d.find('>', at);
    if (end == std::string_view::npos) throw InputError(path + ":" + std::to_string(line_of(at)) + ": <Piece> not closed");
    const std::string_view tag = d.substr(at, end - at);
    // The attribute Source (not a longer name ending in it), '=' with or
    // without spaces around it, then the quoted file name.
    size_t open = std::string_view::npos;
    for (size_t name = tag.find("Source"); name != std::string_view::npos && open == std::string_view::npos;
         name = tag.find("Source", name + 1)) {
      if (name == 0 || !std::isspace(static_cast<unsigned char>(tag[name - 1]))) continue;
      size_t k = name + 6;
      while (k < tag.size() && std::isspace(static_cast<unsigned char>(tag[k]))) ++k;
      if (k >= tag.size() || tag[k] != '=') continue;
      ++k;
      while (k < tag.size() && std::isspace(static_cast<unsigned char>(tag[k]))) ++k;
      if (k < tag.size() && (tag[k] == '"' || tag[k] == '\'')) open = k;
    }
    if (open == std::string_view::npos)
      throw InputError(path + ":" + std::to_string(line_of(at)) + ": a <Piece> without Source=\"FILE\"");
    const size_t close = tag.find(tag[open], open + 1);
    if (close == std::string_view::npos)
      throw InputError(path + ":" + std::to_string(line_of(at)) + ": a <Piece> Source without its closing quote");
    const std::filesystem::path piece = folder / std::string(tag.substr(open + 1, close - open - 1));
    // Sides once the pieces are one: a triangle between two pieces has a
    // tetrahedron in each (taken one piece at a time, the exterior beside it).
    Mesh part = read_vtu_elements(piece.string());
    detail::require_valid(part, piece.string());
    piece_of.resize(whole.points.size() + part.points.size(), static_cast<int>(pieces));
    append_piece(whole, std::move(part));
    ++pieces;
  }
  if (pieces == 0) throw InputError(path + ": lists no <Piece Source=\"FILE\"/>");
  weld_pieces(whole, piece_of);
  detail::require_valid(whole, path);
  detail::sides_from_tets(whole);
  return whole;
}

}  // namespace

Format make_vtu_format() { return {"vtu", {".vtu"}, true, read_vtu, write_vtu, {}}; }
Format make_pvtu_format() { return {"pvtu", {".pvtu"}, true, read_pvtu, nullptr, {}}; }

}  // namespace vd::io
