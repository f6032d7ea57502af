// Shared plumbing of the format readers and writers: file bytes for reading
// (mapped, or gunzipped), a cursor that parses text and binary without iostreams and reports
// "FILE:LINE: what" errors, an output buffer, and mesh post-processing that
// several formats need (welding, region sides from tetrahedra, checks).
#pragma once

#include <algorithm>
#include <charconv>
#include <cstdint>
#include <cstring>
#include <memory>
#include <string>
#include <string_view>
#include <type_traits>
#include <unordered_map>
#include <vector>

#include "converters/registry.h"
#include "mesh/error.h"
#include "mesh/mesh.h"
#include "mesh/parallel.h"

namespace vd::io::detail {

// The bytes of a file for reading: mapped, or gunzipped into memory when the
// name ends in ".gz" (also read into memory when the file cannot be mapped, a
// pipe say). release(pos) drops the mapped pages before `pos` from the
// resident set; they come back from the file if touched again, so it is only
// a hint. A reader that holds the whole file next to the mesh it builds
// peaked at 3 to 9 times the mesh on a 1M-tetrahedron file. Throws InputError.
class FileBytes {
 public:
  explicit FileBytes(const std::string& path);
  ~FileBytes();
  FileBytes(const FileBytes&) = delete;
  FileBytes& operator=(const FileBytes&) = delete;

  std::string_view view() const { return {data_, size_}; }
  operator std::string_view() const { return view(); }
  size_t size() const { return size_; }
  void release(size_t pos) const;
  // The same for the pages wholly inside [begin, end), for readers that
  // visit the file out of order.
  void drop(size_t begin, size_t end) const;

 private:
  const char* data_ = "";
  size_t size_ = 0;
  void* map_ = nullptr;
  std::string owned_;
  mutable size_t released_ = 0;
};

// Lower-case extension with the dot (".msh"), looking through a trailing ".gz".
std::string extension_of(const std::string& path);
// `path` without a trailing ".gz" and without its extension.
std::string strip_extension(const std::string& path);
std::string to_lower(std::string_view s);
std::string to_upper(std::string_view s);
bool iequals(std::string_view a, std::string_view b);
bool starts_with_ci(std::string_view s, std::string_view prefix);
bool ends_with_ci(std::string_view s, std::string_view suffix);

// Never reserve more than the file could hold: counts come from the input.
inline size_t capped(uint64_t count, size_t file_bytes, size_t min_bytes_per_item) {
  const uint64_t most = file_bytes / (min_bytes_per_item ? min_bytes_per_item : 1) + 1;
  return static_cast<size_t>(count < most ? count : most);
}

// A read position in a loaded file. Text tokens are separated by white space
// (optionally commas); `comment` starts a comment to the end of the line.
// Binary reads share the position, so mixed files (Gmsh, legacy VTK) need one
// cursor. Errors name the line while no binary was read, else the byte offset.
class Cursor {
 public:
  Cursor(std::string_view data, std::string name) : data_(data), name_(std::move(name)) {}
  // Over a whole file: the pages the cursor has passed are released as it goes.
  Cursor(const FileBytes& file, std::string name) : data_(file.view()), name_(std::move(name)), file_(&file) {}

  void set_comment(char c) { comment_ = c; }
  void set_comma_separates(bool on) { comma_ = on; }

  // Skips blanks, newlines and comments; true at the end of the data.
  bool at_end();
  // The next token; fails at the end of the data.
  std::string_view token(const char* what);
  // The next token on the current line, or "" when the line has no more.
  std::string_view token_in_line();
  bool line_has_more();
  // Moves to the start of the next line.
  void skip_line();
  // The rest of the current line (without the newline), moving past it.
  std::string_view rest_of_line();
  // The next non-empty line, trimmed, moving past it; "" at end of data.
  std::string_view next_line();

  int64_t integer(const char* what);
  int int32(const char* what);
  // A count: non-negative and at most `limit`.
  uint64_t count(const char* what, uint64_t limit = UINT64_C(1) << 40);
  double real(const char* what);  // finite only
  // The same, but the value must be on the current line.
  double real_in_line(const char* what);
  // Parses a whole token as a number; false when it is not one.
  static bool parse_int(std::string_view t, int64_t& v);
  static bool parse_real(std::string_view t, double& v);

  // Binary: `n` bytes copied out; fails when the data ends first.
  void raw(void* out, size_t n, const char* what) {
    if (n > data_.size() - pos_) fail_inside(what);
    binary_ = true;
    std::memcpy(out, data_.data() + pos_, n);
    pos_ += n;
    if (pos_ >= next_release_) release_passed();
  }
  template <class T>
  T get(const char* what) {
    T v;
    raw(&v, sizeof v, what);
    return v;
  }
  template <class T>
  T get_be(const char* what) {
    unsigned char b[sizeof(T)];
    raw(b, sizeof b, what);
    for (size_t i = 0; i < sizeof(T) / 2; ++i) std::swap(b[i], b[sizeof(T) - 1 - i]);
    T v;
    std::memcpy(&v, b, sizeof v);
    return v;
  }
  // Skips exactly one line end ("\n" or "\r\n") when there is one.
  void skip_newline();
  void skip_bytes(uint64_t n, const char* what);

  size_t pos() const { return pos_; }
  void seek(size_t p) { pos_ = p < data_.size() ? p : data_.size(); }
  size_t line() const { return line_; }
  size_t remaining() const { return data_.size() - pos_; }
  std::string_view data() const { return data_; }
  // Lets the pages wholly inside [begin, end) go, for a look-ahead that read
  // past the cursor (a no-op over plain memory).
  void drop(size_t begin, size_t end) const {
    if (file_) file_->drop(begin, end);
  }
  const std::string& name() const { return name_; }

  [[noreturn]] void fail(const std::string& what) const;

 private:
  static constexpr size_t kReleaseStep = size_t{1} << 20;
  [[noreturn]] void fail_inside(const char* what);
  void release_passed();
  void skip_blanks_in_line();
  std::string_view data_;
  std::string name_;
  size_t pos_ = 0;
  size_t line_ = 1;
  char comment_ = 0;
  bool comma_ = false;
  bool binary_ = false;
  const FileBytes* file_ = nullptr;
  size_t next_release_ = kReleaseStep;
};

// Writes a file through a buffer: once the buffer holds a chunk it goes to
// PATH.part (gzipped for ".gz"), and finish() renames that to PATH; a writer
// that throws before finish() leaves no file (write_target says where PATH
// is, and when it is written in place). A whole 1M-tetrahedron file in
// memory was most of a writer's peak.
class Out {
 public:
  explicit Out(const std::string& path);
  ~Out();
  Out(const Out&) = delete;
  Out& operator=(const Out&) = delete;

  Out& operator<<(std::string_view s) {
    buf_.append(s.data(), s.size());
    return spill_if_full();
  }
  Out& operator<<(char c) {
    buf_.push_back(c);
    return spill_if_full();
  }
  Out& operator<<(const char* s) { return *this << std::string_view(s); }
  Out& operator<<(const std::string& s) { return *this << std::string_view(s); }
  Out& operator<<(int v) { return integer(v); }
  Out& operator<<(long v) { return integer(v); }
  Out& operator<<(long long v) { return integer(v); }
  Out& operator<<(unsigned v) { return integer(v); }
  Out& operator<<(unsigned long v) { return integer(static_cast<long long>(v)); }
  Out& operator<<(double v);  // shortest text that reads back exactly
  Out& integer(long long v);
  template <class T>
  void raw(T v) {
    buf_.append(reinterpret_cast<const char*>(&v), sizeof v);
    spill_if_full();
  }
  // `count` values in one append (a binary element is one call, not five).
  template <class T>
  void raw_n(const T* v, size_t count) {
    buf_.append(reinterpret_cast<const char*>(v), count * sizeof(T));
    spill_if_full();
  }
  template <class T>
  void raw_be(T v) {
    char b[sizeof(T)];
    std::memcpy(b, &v, sizeof v);
    for (size_t i = 0; i < sizeof(T) / 2; ++i) std::swap(b[i], b[sizeof(T) - 1 - i]);
    buf_.append(b, sizeof b);
    spill_if_full();
  }
  // Replaces the last byte written (a separator becoming a line end); the
  // streaming buffer always keeps it.
  void replace_last(char c) {
    if (!buf_.empty()) buf_.back() = c;
  }
  // For appending in place (base64); call spill_if_full() after.
  std::string& str() { return buf_; }
  Out& spill_if_full() {
    if (buf_.size() >= kChunk && sink_) spill();
    return *this;
  }
  // Writes the rest and gives the file its name.
  void finish();

 private:
  static constexpr size_t kChunk = size_t{1} << 20;
  struct Sink;
  void spill();
  std::string buf_;
  std::unique_ptr<Sink> sink_;
};

// Writes value(0) .. value(n - 1) as text, per_line to a line, separated by
// spaces: integers as integers, floating point as the shortest text that
// reads back exactly (as Out's <<). The text is made in pieces on all
// threads and appended in order, a few pieces at a time so that an array's
// text never exists whole: the connectivity of a surface-only run on the
// bunny was a tenth of its time formatted on one thread.
template <class Value>
void write_text_values(Out& out, size_t n, size_t per_line, Value value) {
  using T = decltype(value(size_t{0}));
  constexpr size_t kPiece = size_t{1} << 15;   // values
  constexpr size_t kWidest = 26;               // a double's text and a separator
  const size_t pieces = (n + kPiece - 1) / kPiece;
  const size_t batch = 2 * static_cast<size_t>(std::max(1, thread_count()));
  std::vector<std::string> text(std::min(batch, pieces));
  for (size_t first = 0; first < pieces; first += batch) {
    const size_t count = std::min(batch, pieces - first);
    for_each_chunk(static_cast<long>(count), 1, [&](long k, long, long) {
      const size_t begin = (first + static_cast<size_t>(k)) * kPiece, end = std::min(n, begin + kPiece);
      std::string& t = text[static_cast<size_t>(k)];
      t.resize((end - begin) * kWidest);
      char* at = t.data();
      for (size_t i = begin; i < end; ++i) {
        const T v = value(i);
        if constexpr (std::is_floating_point_v<T>) at = std::to_chars(at, at + kWidest, static_cast<double>(v)).ptr;
        else at = std::to_chars(at, at + kWidest, static_cast<long long>(v)).ptr;
        *at++ = (i + 1) % per_line == 0 || i + 1 == n ? '\n' : ' ';
      }
      t.resize(static_cast<size_t>(at - t.data()));
    });
    for (size_t k = 0; k < count; ++k) out << text[k];
  }
}

// Element or node number -> index: a vector while the numbers stay within
// about twice the count (what every writer produces), a hash map beyond, so
// no allocation follows a number's size.
class IdIndex {
 public:
  // Sizes the vector for `expected` numbers (capped by what the file holds).
  void expect(uint64_t expected, size_t file_bytes) { dense_.assign(capped(expected, file_bytes, 4) * 2 + 1024, -1); }
  // False when `id` is there already.
  bool add(int64_t id, int index) {
    const uint64_t u = static_cast<uint64_t>(id);
    if (id >= 0 && u >= dense_.size() && u < 2 * (count_ + 512))
      dense_.resize(std::max<size_t>(static_cast<size_t>(u) + 1, std::min<size_t>(2 * dense_.size(), 2 * (count_ + 512))), -1);
    ++count_;
    if (id >= 0 && u < dense_.size()) {
      if (dense_[u] >= 0) return false;
      dense_[u] = index;
      return true;
    }
    return sparse_.emplace(id, index).second;
  }
  // Moves `id` (which is there) to `index`.
  void set(int64_t id, int index) {
    const uint64_t u = static_cast<uint64_t>(id);
    if (id >= 0 && u < dense_.size()) dense_[u] = index;
    else sparse_[id] = index;
  }
  // -1 when `id` is not there.
  int find(int64_t id) const {
    const uint64_t u = static_cast<uint64_t>(id);
    if (id >= 0 && u < dense_.size()) return dense_[u];
    auto it = sparse_.find(id);
    return it == sparse_.end() ? -1 : it->second;
  }

 private:
  std::vector<int> dense_;
  std::unordered_map<int64_t, int> sparse_;
  size_t count_ = 0;
};

// Element numbers in file order, 4 bytes each while they fit.
class TagList {
 public:
  void reserve(size_t n) { narrow_.reserve(n); }
  void push_back(uint64_t t) {
    if (wide_.empty() && t <= UINT32_MAX) return narrow_.push_back(static_cast<uint32_t>(t));
    if (wide_.empty()) {
      wide_.assign(narrow_.begin(), narrow_.end());
      narrow_ = {};
    }
    wide_.push_back(t);
  }
  size_t size() const { return wide_.empty() ? narrow_.size() : wide_.size(); }
  uint64_t operator[](size_t i) const { return wide_.empty() ? narrow_[i] : wide_[i]; }
  void swap_items(size_t i, size_t j) {
    if (wide_.empty()) std::swap(narrow_[i], narrow_[j]);
    else std::swap(wide_[i], wide_[j]);
  }

 private:
  std::vector<uint32_t> narrow_;
  std::vector<uint64_t> wide_;
};

// Puts items 0..n-1 in the order of key(i), stable, moving them only with
// swap(i, j), which must swap everything that belongs to an item (its key
// too). Keys that are a permutation of a range are placed by following
// cycles; other keys through a sorted index. No item is copied: a sorted
// copy of 1M tetrahedra was a quarter of a reader's peak.
template <class Key, class Swap>
void sort_in_place(size_t n, Key key, Swap swap) {
  bool sorted = true;
  uint64_t lo = n ? key(0) : 0, hi = lo;
  for (size_t i = 1; i < n; ++i) {
    const uint64_t k = key(i);
    sorted = sorted && key(i - 1) <= k;
    lo = std::min(lo, k);
    hi = std::max(hi, k);
  }
  if (sorted) return;
  bool dense = hi - lo + 1 == n;
  if (dense) {
    std::vector<bool> seen(n, false);
    for (size_t i = 0; i < n && dense; ++i) {
      const size_t at = static_cast<size_t>(key(i) - lo);
      dense = !seen[at];
      seen[at] = true;
    }
  }
  if (dense) {
    for (size_t i = 0; i < n; ++i)
      while (key(i) - lo != i) swap(i, static_cast<size_t>(key(i) - lo));
    return;
  }
  std::vector<size_t> order(n), target(n);
  for (size_t i = 0; i < n; ++i) order[i] = i;
  std::stable_sort(order.begin(), order.end(), [&](size_t a, size_t b) { return key(a) < key(b); });
  for (size_t k = 0; k < n; ++k) target[order[k]] = k;
  for (size_t i = 0; i < n; ++i)
    while (target[i] != i) {
      const size_t j = target[i];
      swap(i, j);
      std::swap(target[i], target[j]);
    }
}

// Keeps the elements `keep(element)` accepts, in order, with their mid-edge
// nodes when every element has them (the other rows are left as they are).
template <class Element, class Mid, class Keep>
void keep_elements_if(std::vector<Element>& elements, std::vector<Mid>& mids, Keep keep) {
  const bool with_mids = mids.size() == elements.size();
  size_t kept = 0;
  for (size_t i = 0; i < elements.size(); ++i) {
    if (!keep(elements[i])) continue;
    if (with_mids) mids[kept] = mids[i];
    elements[kept++] = elements[i];
  }
  elements.resize(kept);
  if (with_mids) mids.resize(kept);
}

// Puts tetrahedra in the order of their element numbers, in place; their
// mid-edge nodes move with them when every tetrahedron has them.
void sort_tets_by_number(TagList& numbers, std::vector<Tetrahedron>& tets, std::vector<TetMidNodes>& mids);

// Fills each triangle's unknown front/back from the tetrahedra that have it as
// a face; a side without a tetrahedron is the exterior (0). Triangles that
// are no tetrahedron's face keep unknown sides.
void sides_from_tets(Mesh& m);
// True when the triangles' sides, where known, enclose each region they
// name: its facets, turned out of it, run every edge once each way, and
// enclose a positive volume. A reader whose file states the sides apart
// from the triangles (Gmsh 4.1's $Entities) checks them with this.
bool sides_close_regions(const Mesh& m);
// A triangle's corners for a format that cannot say which region lies on
// which side (OFF, STL, OBJ; Medit, Gmsh 2.2, TetGen and Abaqus files without
// tetrahedra): turned, when both sides are known, so that the
// normal points into the lower-numbered region (out of a solid, into the
// exterior). A CAD tessellation keeps each face's own orientation and says
// the sides in the tags; written as they were, gmsh_part.step's surface had
// 2,364 of its 5,560 facets turned in, and no program, vdmesh included,
// could read it back as a closed surface.
std::array<int, 3> corners_without_sides(const Triangle& t);
// Its mid-edge nodes (edges v0v1, v1v2, v2v0) in the order of those corners.
TriMidNodes mid_nodes_without_sides(const Triangle& t, const TriMidNodes& mid);
// The points a surface format lists: for a volume mesh the triangles'
// corners only (`kept`, in the points' order; `number` each point's number
// among them, -1 for the others), else every point. A volume mesh written
// as OFF listed its interior points as isolated vertices (647 vertices for
// 185 triangles), and a .poly made TetGen keep every one of them.
struct SurfacePoints {
  std::vector<int> kept;
  std::vector<int> number;
};
SurfacePoints surface_points(const Mesh& m);
// The region ids used by the tetrahedra, and the face ids of the triangles.
std::vector<int> region_ids(const Mesh& m);
std::vector<int> face_ids(const Mesh& m);
// Name of a region / face for formats that store names.
std::string region_name(const Mesh& m, int region);
std::string face_name(const Mesh& m, int face);
// When `name` is "<prefix><k>" (case-insensitive) returns k, else -1.
int id_from_name(std::string_view name, std::string_view prefix);
// A tetrahedron's signed volume x 6.
double tet_det(const Mesh& m, const std::array<int, 4>& v);

}  // namespace vd::io::detail

namespace vd::io::detail {
// Throws InputError naming `name` when an element refers to a missing point,
// or side arrays do not match their elements, or the triangles are second
// order beside first-order tetrahedra: a last guard after parsing.
void require_valid(const Mesh& m, const std::string& name);
// Second-order tetrahedra beside first-order triangles (a file may list the
// boundary with its corners only): gives each triangle the mid-edge nodes of
// its edges in the tetrahedra. Throws InputError naming `name` and the
// triangle when one of its edges is no tetrahedron's.
void complete_triangle_mids(Mesh& m, const std::string& name);
}  // namespace vd::io::detail
