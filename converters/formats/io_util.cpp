#include "io_util.h"

#include <fcntl.h>
#include <signal.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>
#include <zlib.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <cstring>
#include <ctime>
#include <filesystem>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <memory>
#include <optional>
#include <set>
#include <unordered_map>

namespace vd::io::detail {

bool ends_with_ci(std::string_view s, std::string_view suffix) {
  return s.size() >= suffix.size() && iequals(s.substr(s.size() - suffix.size()), suffix);
}

namespace {

// "path: what: the system's reason", with the error number (taken before
// anything else can change errno).
FileError file_error(const std::string& path, const char* what, int error_number) {
  return FileError(path + ": " + what + ": " + std::strerror(error_number), path, error_number);
}

std::string gunzip(const std::string& path) {
  gzFile f = gzopen(path.c_str(), "rb");
  if (!f) throw file_error(path, "cannot open", errno);
  std::string out;
  std::vector<char> chunk(1 << 16);
  for (;;) {
    const int n = gzread(f, chunk.data(), static_cast<unsigned>(chunk.size()));
    if (n < 0) {
      int code = 0;
      const std::string msg = gzerror(f, &code);
      gzclose(f);
      throw InputError(path + ": byte " + std::to_string(out.size()) + ": bad gzip data: " + msg);
    }
    if (n == 0) break;
    out.append(chunk.data(), static_cast<size_t>(n));
  }
  gzclose(f);
  return out;
}

}  // namespace

std::string to_lower(std::string_view s) {
  std::string r(s);
  for (char& c : r) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return r;
}

std::string to_upper(std::string_view s) {
  std::string r(s);
  for (char& c : r) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  return r;
}

bool iequals(std::string_view a, std::string_view b) {
  if (a.size() != b.size()) return false;
  for (size_t i = 0; i < a.size(); ++i)
    if (std::tolower(static_cast<unsigned char>(a[i])) != std::tolower(static_cast<unsigned char>(b[i])))
      return false;
  return true;
}

bool starts_with_ci(std::string_view s, std::string_view prefix) {
  return s.size() >= prefix.size() && iequals(s.substr(0, prefix.size()), prefix);
}

std::string extension_of(const std::string& path) {
  std::string_view p(path);
  if (ends_with_ci(p, ".gz")) p.remove_suffix(3);
  const size_t slash = p.find_last_of("/\\");
  const size_t dot = p.rfind('.');
  if (dot == std::string_view::npos || (slash != std::string_view::npos && dot < slash)) return "";
  return to_lower(p.substr(dot));
}

std::string strip_extension(const std::string& path) {
  std::string_view p(path);
  if (ends_with_ci(p, ".gz")) p.remove_suffix(3);
  const std::string ext = extension_of(path);
  return std::string(p.substr(0, p.size() - ext.size()));
}

FileBytes::FileBytes(const std::string& path) {
  std::error_code folder_check;
  if (std::filesystem::is_directory(path, folder_check)) throw FileError(path + ": cannot open: it is a directory", path, EISDIR);
  if (ends_with_ci(path, ".gz")) {
    owned_ = gunzip(path);
  } else {
    const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
    if (fd < 0) throw file_error(path, "cannot open", errno);
    struct stat st {};
    const bool have_stat = ::fstat(fd, &st) == 0;
    if (have_stat && S_ISDIR(st.st_mode)) {
      ::close(fd);
      throw FileError(path + ": cannot open: it is a directory", path, EISDIR);
    }
    if (have_stat && S_ISREG(st.st_mode) && st.st_size > 0) {
      void* p = ::mmap(nullptr, static_cast<size_t>(st.st_size), PROT_READ, MAP_PRIVATE, fd, 0);
      if (p != MAP_FAILED) {
        map_ = p;
        data_ = static_cast<const char*>(p);
        size_ = static_cast<size_t>(st.st_size);
        ::madvise(p, size_, MADV_SEQUENTIAL);
        ::close(fd);
        return;
      }
    }
    // Not a regular file (or not mappable): read it.
    char chunk[1 << 16];
    for (;;) {
      const ssize_t n = ::read(fd, chunk, sizeof chunk);
      if (n < 0 && errno == EINTR) continue;
      if (n < 0) {
        const int err = errno;
        ::close(fd);
        throw file_error(path, "read error", err);
      }
      if (n == 0) break;
      owned_.append(chunk, static_cast<size_t>(n));
    }
    ::close(fd);
  }
  data_ = owned_.data();
  size_ = owned_.size();
}

FileBytes::~FileBytes() {
  if (map_) ::munmap(map_, size_);
}

void FileBytes::release(size_t pos) const {
  if (pos <= released_) return;
  drop(released_, pos);
  released_ = pos;
}

void FileBytes::drop(size_t begin, size_t end) const {
  if (!map_) return;
  static const size_t page = static_cast<size_t>(::sysconf(_SC_PAGESIZE));
  const size_t from = (begin + page - 1) / page * page, to = std::min(end, size_) / page * page;
  if (to > from) ::madvise(static_cast<char*>(map_) + from, to - from, MADV_DONTNEED);
}

// ---------------------------------------------------------------------------
// Cursor

void Cursor::fail(const std::string& what) const {
  if (binary_) throw InputError(name_ + ": byte " + std::to_string(pos_) + ": " + what);
  throw InputError(name_ + ":" + std::to_string(line_) + ": " + what);
}

void Cursor::skip_blanks_in_line() {
  while (pos_ < data_.size()) {
    const char c = data_[pos_];
    if (c == ' ' || c == '\t' || c == '\r' || c == '\f' || c == '\v' || (comma_ && c == ',')) {
      ++pos_;
    } else if (comment_ && c == comment_) {
      while (pos_ < data_.size() && data_[pos_] != '\n') ++pos_;
    } else {
      break;
    }
  }
}

bool Cursor::at_end() {
  for (;;) {
    skip_blanks_in_line();
    if (pos_ >= data_.size()) return true;
    if (data_[pos_] != '\n') return false;
    ++pos_;
    ++line_;
  }
}

bool Cursor::line_has_more() {
  skip_blanks_in_line();
  return pos_ < data_.size() && data_[pos_] != '\n';
}

std::string_view Cursor::token_in_line() {
  if (!line_has_more()) return {};
  const size_t start = pos_;
  while (pos_ < data_.size()) {
    const char c = data_[pos_];
    if (c == ' ' || c == '\t' || c == '\r' || c == '\n' || c == '\f' || c == '\v' ||
        (comma_ && c == ',') || (comment_ && c == comment_))
      break;
    ++pos_;
  }
  if (pos_ >= next_release_) release_passed();
  return data_.substr(start, pos_ - start);
}

std::string_view Cursor::token(const char* what) {
  if (at_end()) fail(std::string("unexpected end of file, expected ") + what);
  return token_in_line();
}

void Cursor::skip_line() {
  while (pos_ < data_.size() && data_[pos_] != '\n') ++pos_;
  if (pos_ < data_.size()) {
    ++pos_;
    ++line_;
  }
  if (pos_ >= next_release_) release_passed();
}

std::string_view Cursor::rest_of_line() {
  const size_t start = pos_;
  while (pos_ < data_.size() && data_[pos_] != '\n') ++pos_;
  std::string_view r = data_.substr(start, pos_ - start);
  if (pos_ < data_.size()) {
    ++pos_;
    ++line_;
  }
  while (!r.empty() && (r.back() == '\r' || r.back() == ' ' || r.back() == '\t')) r.remove_suffix(1);
  return r;
}

std::string_view Cursor::next_line() {
  while (!at_end()) {
    std::string_view r = rest_of_line();
    while (!r.empty() && (r.front() == ' ' || r.front() == '\t')) r.remove_prefix(1);
    if (comment_) {
      const size_t c = r.find(comment_);
      if (c != std::string_view::npos) r = r.substr(0, c);
      while (!r.empty() && (r.back() == ' ' || r.back() == '\t')) r.remove_suffix(1);
    }
    if (!r.empty()) return r;
  }
  return {};
}

bool Cursor::parse_int(std::string_view t, int64_t& v) {
  if (!t.empty() && t[0] == '+') t.remove_prefix(1);
  if (t.empty()) return false;
  const auto [p, ec] = std::from_chars(t.data(), t.data() + t.size(), v);
  return ec == std::errc() && p == t.data() + t.size();
}

bool Cursor::parse_real(std::string_view t, double& v) {
  if (!t.empty() && t[0] == '+') t.remove_prefix(1);
  if (t.empty()) return false;
  const auto [p, ec] = std::from_chars(t.data(), t.data() + t.size(), v);
  if (ec == std::errc::result_out_of_range) return false;
  return ec == std::errc() && p == t.data() + t.size() && std::isfinite(v);
}

int64_t Cursor::integer(const char* what) {
  const std::string_view t = token(what);
  int64_t v;
  if (!parse_int(t, v)) fail(std::string("expected ") + what + " (an integer), found '" +
                             std::string(t.substr(0, 40)) + "'");
  return v;
}

int Cursor::int32(const char* what) {
  const int64_t v = integer(what);
  if (v < INT32_MIN || v > INT32_MAX) fail(std::string(what) + " out of range: " + std::to_string(v));
  return static_cast<int>(v);
}

uint64_t Cursor::count(const char* what, uint64_t limit) {
  const int64_t v = integer(what);
  if (v < 0) fail(std::string("negative ") + what + ": " + std::to_string(v));
  if (static_cast<uint64_t>(v) > limit) fail(std::string(what) + " too large: " + std::to_string(v));
  return static_cast<uint64_t>(v);
}

double Cursor::real(const char* what) {
  const std::string_view t = token(what);
  double v;
  if (!parse_real(t, v))
    fail(std::string("expected ") + what + " (a finite number), found '" + std::string(t.substr(0, 40)) + "'");
  return v;
}

double Cursor::real_in_line(const char* what) {
  if (!line_has_more()) fail(std::string("missing ") + what);
  return real(what);
}

void Cursor::fail_inside(const char* what) {
  binary_ = true;
  fail(std::string("file ends inside ") + what);
}

void Cursor::release_passed() {
  // Keep a step behind: a reader may still look at what it just parsed.
  if (file_ && pos_ > kReleaseStep) file_->release(pos_ - kReleaseStep);
  next_release_ = pos_ + kReleaseStep;
}

void Cursor::skip_bytes(uint64_t n, const char* what) {
  binary_ = true;
  if (n > data_.size() - pos_) fail(std::string("file ends inside ") + what);
  pos_ += static_cast<size_t>(n);
  if (pos_ >= next_release_) release_passed();
}

void Cursor::skip_newline() {
  if (pos_ < data_.size() && data_[pos_] == '\r') ++pos_;
  if (pos_ < data_.size() && data_[pos_] == '\n') {
    ++pos_;
    ++line_;
  }
}

// ---------------------------------------------------------------------------
// Out

struct Out::Sink {
  std::string path, part;       // part == path when written in place
  bool in_place = false;
  std::optional<std::filesystem::perms> perms;
  FILE* file = nullptr;
  gzFile gz = nullptr;
  void write(const char* data, size_t n) {
    while (n > 0) {
      const size_t step = std::min<size_t>(n, 1u << 30);
      errno = 0;  // gzwrite need not set it: an earlier call's would be reported
      const bool ok = gz ? gzwrite(gz, data, static_cast<unsigned>(step)) == static_cast<int>(step)
                         : std::fwrite(data, 1, step, file) == step;
      if (!ok) throw FileError(path + ": write error", path, errno ? errno : EIO);
      data += step;
      n -= step;
    }
  }
  // Closes; true when everything reached the file.
  bool close() {
    bool ok = true;
    if (gz) ok = gzclose(gz) == Z_OK;
    if (file) ok = std::fclose(file) == 0;
    gz = nullptr;
    file = nullptr;
    return ok;
  }
};

}  // namespace vd::io::detail

namespace vd::io {

WriteTarget write_target(const std::string& path) {
  namespace fs = std::filesystem;
  WriteTarget t{path, false, std::nullopt};
  std::error_code ec;
  if (fs::is_symlink(path, ec)) {
    const fs::path resolved = fs::weakly_canonical(path, ec);
    if (!ec) t.path = resolved.string();
  }
  const fs::file_status st = fs::status(t.path, ec);
  if (ec || !fs::exists(st)) return t;
  if (!fs::is_regular_file(st)) t.in_place = true;
  else t.perms = st.permissions();
  return t;
}

void remove_stale_parts(const std::string& path) {
  // Only the names vdmesh makes: PATH.part.<pid>.<n>, a file (a write's
  // part), or PATH.part.<pid>.<6 characters>, a folder (vdmesh mesh -o's
  // staging); ours, of a process that does not run here, and untouched for
  // ten minutes (a writer in another process namespace, sharing the folder,
  // would look dead by its pid). A user's x.msh.part.12.txt was removed by
  // the first version of this (a review, 2026-11-30).
  namespace fs = std::filesystem;
  const fs::path target(path);
  const std::string prefix = target.filename().string() + ".part.";
  const fs::path folder = target.has_parent_path() ? target.parent_path() : fs::path(".");
  const auto digits = [](std::string_view s) {
    return !s.empty() && std::all_of(s.begin(), s.end(), [](char c) { return c >= '0' && c <= '9'; });
  };
  std::error_code ec;
  for (fs::directory_iterator it(folder, ec), end; !ec && it != end; it.increment(ec)) {
    const std::string name = it->path().filename().string();
    if (name.compare(0, prefix.size(), prefix) != 0) continue;
    const std::string_view rest = std::string_view(name).substr(prefix.size());
    const size_t dot = rest.find('.');
    if (dot == std::string_view::npos || !digits(rest.substr(0, dot)) || dot > 9) continue;
    const std::string_view tail = rest.substr(dot + 1);
    struct stat st {};
    if (::lstat(it->path().c_str(), &st) != 0 || st.st_uid != ::getuid()) continue;
    const bool part_file = S_ISREG(st.st_mode) && digits(tail) && tail.size() <= 20;
    const bool staging = S_ISDIR(st.st_mode) && tail.size() == 6;
    if (!part_file && !staging) continue;
    const long pid = std::stol(std::string(rest.substr(0, dot)));
    if (pid <= 0 || pid == ::getpid() || ::kill(static_cast<pid_t>(pid), 0) == 0 || errno != ESRCH) continue;
    time_t newest = st.st_mtime;
    if (staging)
      for (fs::directory_iterator in(it->path(), ec), none; !ec && in != none; in.increment(ec)) {
        struct stat inner {};
        if (::lstat(in->path().c_str(), &inner) == 0) newest = std::max(newest, inner.st_mtime);
      }
    ec.clear();
    if (std::time(nullptr) - newest < 600) continue;
    std::error_code ignored;
    fs::remove_all(it->path(), ignored);
  }
}

}  // namespace vd::io

namespace vd::io::detail {

Out::Out(const std::string& path) {
  auto sink = std::make_unique<Sink>();
  const WriteTarget target = write_target(path);
  sink->path = target.path;
  sink->in_place = target.in_place;
  sink->perms = target.perms;
  // A name of its own per write, created exclusively: two threads writing
  // the same path shared PATH.part, and the reader of the result found it
  // empty or cut (a Python tester, 2026-11-30).
  static std::atomic<unsigned long> writes{0};
  if (!target.in_place) remove_stale_parts(target.path);
  const bool gz = ends_with_ci(path, ".gz");
  for (int attempt = 0;; ++attempt) {
    sink->part = target.in_place ? target.path
                                 : target.path + ".part." + std::to_string(::getpid()) + "." +
                                       std::to_string(writes.fetch_add(1));
    const char* mode = target.in_place ? (gz ? "wb6" : "wb") : (gz ? "wb6x" : "wbx");
    if (gz) sink->gz = gzopen(sink->part.c_str(), mode);
    else sink->file = std::fopen(sink->part.c_str(), mode);
    if (sink->gz || sink->file) break;
    if (errno != EEXIST || attempt == 100) throw file_error(path, "cannot write", errno);
  }
  sink_ = std::move(sink);
  buf_.reserve(kChunk + (kChunk >> 2));
}

Out::~Out() {
  if (!sink_) return;
  sink_->close();
  if (!sink_->in_place) std::remove(sink_->part.c_str());
}

void Out::spill() {
  // All but the last byte, which replace_last() may still change.
  const size_t n = buf_.size() - 1;
  sink_->write(buf_.data(), n);
  buf_.erase(0, n);
}

void Out::finish() {
  if (!sink_) return;
  sink_->write(buf_.data(), buf_.size());
  buf_.clear();
  errno = 0;
  if (!sink_->close()) throw FileError(sink_->path + ": write error", sink_->path, errno ? errno : EIO);
  if (!sink_->in_place) {
    // The file replaced keeps its permissions (a 0600 deck became 0644).
    std::error_code ignored;
    if (sink_->perms) std::filesystem::permissions(sink_->part, *sink_->perms, ignored);
    if (std::rename(sink_->part.c_str(), sink_->path.c_str()) != 0)
      throw file_error(sink_->path, "cannot write", errno);
  }
  sink_.reset();
}

Out& Out::integer(long long v) {
  char b[24];
  const auto r = std::to_chars(b, b + sizeof b, v);
  buf_.append(b, static_cast<size_t>(r.ptr - b));
  return spill_if_full();
}

Out& Out::operator<<(double v) {
  char b[32];
  const auto r = std::to_chars(b, b + sizeof b, v);
  buf_.append(b, static_cast<size_t>(r.ptr - b));
  return spill_if_full();
}

// ---------------------------------------------------------------------------
// Mesh helpers

double tet_det(const Mesh& m, const std::array<int, 4>& v) {
  const Vec3 a = m.points[static_cast<size_t>(v[0])];
  return dot(cross(m.points[static_cast<size_t>(v[1])] - a, m.points[static_cast<size_t>(v[2])] - a),
             m.points[static_cast<size_t>(v[3])] - a);
}

bool sides_close_regions(const Mesh& m) {
  std::vector<std::array<int, 3>> edges, twins;  // (region, from, to), and the reverse
  std::map<int, double> volume;                    // by region, x 6
  for (const Triangle& t : m.triangles) {
    if (t.front == t.back) continue;  // a crack's edges run both ways
    for (const int r : {t.front, t.back}) {
      if (r <= 0) continue;
      // Out of r: the normal points from back to front.
      const std::array<int, 3> v = r == t.back ? t.v : std::array<int, 3>{t.v[0], t.v[2], t.v[1]};
      for (int k = 0; k < 3; ++k) {
        edges.push_back({r, v[k], v[(k + 1) % 3]});
        twins.push_back({r, v[(k + 1) % 3], v[k]});
      }
      const Vec3 &a = m.points[static_cast<size_t>(v[0])], &b = m.points[static_cast<size_t>(v[1])],
                 &c = m.points[static_cast<size_t>(v[2])];
      volume[r] += dot(a, cross(b, c));
    }
  }
  std::sort(edges.begin(), edges.end());
  std::sort(twins.begin(), twins.end());
  if (edges != twins) return false;
  for (const auto& [r, v] : volume)
    if (!(v > 0)) return false;
  return true;
}

void sides_from_tets(Mesh& m) {
  if (m.tets.empty() || m.triangles.empty()) return;
  // Triangles sorted by their vertex set; tetrahedron faces are looked up.
  using Key = std::array<int, 3>;
  auto key_of = [](int a, int b, int c) {
    Key k{a, b, c};
    std::sort(k.begin(), k.end());
    return k;
  };
  std::vector<std::pair<Key, int>> index;
  index.reserve(m.triangles.size());
  for (size_t i = 0; i < m.triangles.size(); ++i) {
    const Triangle& t = m.triangles[i];
    if (t.front == kUnknownRegion || t.back == kUnknownRegion)
      index.push_back({key_of(t.v[0], t.v[1], t.v[2]), static_cast<int>(i)});
  }
  if (index.empty()) return;
  std::sort(index.begin(), index.end());
  std::vector<int> front(m.triangles.size(), kUnknownRegion - 1), back(front);
  // Most tetrahedron faces have a vertex off every triangle; a flag per node
  // rejects them before the sort and the search (they were most of the time).
  std::vector<char> on_triangle(m.points.size(), 0);
  for (const auto& entry : index)
    for (int v : entry.first) on_triangle[static_cast<size_t>(v)] = 1;
  // Faces of a positive tetrahedron (a,b,c,d) whose normal points into it.
  static const int inward[4][3] = {{1, 3, 2}, {0, 2, 3}, {0, 3, 1}, {0, 1, 2}};
  for (const Tetrahedron& tet : m.tets) {
    int touching = 0;
    for (int v : tet.v) touching += on_triangle[static_cast<size_t>(v)];
    if (touching < 3) continue;
    const bool positive = tet_det(m, tet.v) >= 0;
    for (const auto& f : inward) {
      const int a = tet.v[f[0]], b = tet.v[f[1]], c = tet.v[f[2]];
      if (!on_triangle[static_cast<size_t>(a)] || !on_triangle[static_cast<size_t>(b)] ||
          !on_triangle[static_cast<size_t>(c)])
        continue;
      const Key k = key_of(a, b, c);
      auto it = std::lower_bound(index.begin(), index.end(), std::make_pair(k, -1));
      for (; it != index.end() && it->first == k; ++it) {
        const Triangle& t = m.triangles[static_cast<size_t>(it->second)];
        // Same cyclic order as the inward face: the tetrahedron is in front.
        const int s = (t.v[0] == a) ? 0 : (t.v[1] == a ? 1 : 2);
        const bool same = t.v[(s + 1) % 3] == b;
        const bool in_front = same == positive;
        (in_front ? front : back)[static_cast<size_t>(it->second)] = tet.region;
      }
    }
  }
  for (const auto& [k, i] : index) {
    Triangle& t = m.triangles[static_cast<size_t>(i)];
    const size_t u = static_cast<size_t>(i);
    const bool hit_front = front[u] != kUnknownRegion - 1, hit_back = back[u] != kUnknownRegion - 1;
    if (!hit_front && !hit_back) continue;
    if (t.front == kUnknownRegion) t.front = hit_front ? front[u] : 0;
    if (t.back == kUnknownRegion) t.back = hit_back ? back[u] : 0;
  }
}

void sort_tets_by_number(TagList& numbers, std::vector<Tetrahedron>& tets, std::vector<TetMidNodes>& mids) {
  const bool with_mids = mids.size() == tets.size();
  sort_in_place(
      tets.size(), [&](size_t i) { return numbers[i]; },
      [&](size_t i, size_t j) {
        numbers.swap_items(i, j);
        std::swap(tets[i], tets[j]);
        if (with_mids) std::swap(mids[i], mids[j]);
      });
}

namespace {
bool turned_without_sides(const Triangle& t) {
  return t.front != kUnknownRegion && t.back != kUnknownRegion && t.front > t.back;
}
}  // namespace

std::array<int, 3> corners_without_sides(const Triangle& t) {
  if (turned_without_sides(t)) return {t.v[0], t.v[2], t.v[1]};
  return t.v;
}

TriMidNodes mid_nodes_without_sides(const Triangle& t, const TriMidNodes& mid) {
  if (turned_without_sides(t)) return {mid[2], mid[1], mid[0]};
  return mid;
}

std::vector<int> region_ids(const Mesh& m) {
  std::set<int> s;
  for (const Tetrahedron& t : m.tets) s.insert(t.region);
  return {s.begin(), s.end()};
}

std::vector<int> face_ids(const Mesh& m) {
  std::set<int> s;
  for (const Triangle& t : m.triangles) s.insert(t.face);
  return {s.begin(), s.end()};
}

std::string region_name(const Mesh& m, int region) {
  auto it = m.region_names.find(region);
  if (it != m.region_names.end() && !it->second.empty()) return it->second;
  return "Region" + std::to_string(region);
}

std::string face_name(const Mesh& m, int face) {
  auto it = m.face_names.find(face);
  if (it != m.face_names.end() && !it->second.empty()) return it->second;
  return "Face" + std::to_string(face);
}

int id_from_name(std::string_view name, std::string_view prefix) {
  if (!starts_with_ci(name, prefix) || name.size() == prefix.size() || name.size() > prefix.size() + 9)
    return -1;
  int v = 0;
  for (char c : name.substr(prefix.size())) {
    if (c < '0' || c > '9') return -1;
    v = v * 10 + (c - '0');
  }
  return v;
}

namespace {

// Tetrahedron edges in Mesh::TetMidNodes order, and an order-free key of an edge.
constexpr int kTetEdge[6][2] = {{0, 1}, {1, 2}, {2, 0}, {0, 3}, {1, 3}, {2, 3}};
uint64_t edge_key(int a, int b) { return (uint64_t(std::min(a, b)) << 32) | uint32_t(std::max(a, b)); }

// Second order: a mid-edge node belongs to one edge, the same in every
// element that lists it, and is no element's corner. Tetrahedra given new
// corners beside the old rows of mid-edge nodes were written with nodes
// 0.25 off their edges on a mesh of unit boxes (a Python tester, 2026-11-30).
void check_mid_nodes(const Mesh& m, const std::string& name) {
  if (m.tet_mid.empty() && m.triangle_mid.empty()) return;
  constexpr uint64_t kFree = ~uint64_t{0}, kCorner = kFree - 1;
  std::vector<uint64_t> edge_of(m.points.size(), kFree);
  for (const Tetrahedron& t : m.tets)
    for (int v : t.v) edge_of[static_cast<size_t>(v)] = kCorner;
  for (const Triangle& t : m.triangles)
    for (int v : t.v) edge_of[static_cast<size_t>(v)] = kCorner;
  const auto claim = [&](int node, int a, int b, const char* what, size_t i) {
    const uint64_t key = edge_key(a, b);
    uint64_t& e = edge_of[static_cast<size_t>(node)];
    if (e == kFree) e = key;
    if (e == key) return;
    throw InputError(name + ": " + what + " " + std::to_string(i + 1) +
                     (e == kCorner ? " has a corner of an element as a mid-edge node"
                                   : " has another edge's mid-edge node (its mid-edge nodes do not follow its corners)"));
  };
  for (size_t i = 0; i < m.tet_mid.size(); ++i)
    for (int e = 0; e < 6; ++e)
      claim(m.tet_mid[i][e], m.tets[i].v[kTetEdge[e][0]], m.tets[i].v[kTetEdge[e][1]], "tetrahedron", i);
  for (size_t i = 0; i < m.triangle_mid.size(); ++i)
    for (int e = 0; e < 3; ++e)
      claim(m.triangle_mid[i][e], m.triangles[i].v[e], m.triangles[i].v[(e + 1) % 3], "triangle", i);
}

}  // namespace

void require_valid(const Mesh& m, const std::string& name) {
  const size_t n = m.points.size();
  auto bad = [&](const std::string& what, size_t i) {
    throw InputError(name + ": " + what + " " + std::to_string(i + 1) + " refers to a node that does not exist");
  };
  for (size_t i = 0; i < m.triangles.size(); ++i)
    for (int v : m.triangles[i].v)
      if (v < 0 || static_cast<size_t>(v) >= n) bad("triangle", i);
  for (size_t i = 0; i < m.tets.size(); ++i)
    for (int v : m.tets[i].v)
      if (v < 0 || static_cast<size_t>(v) >= n) bad("tetrahedron", i);
  for (size_t i = 0; i < m.triangle_mid.size(); ++i)
    for (int v : m.triangle_mid[i])
      if (v < 0 || static_cast<size_t>(v) >= n) bad("triangle", i);
  for (size_t i = 0; i < m.tet_mid.size(); ++i)
    for (int v : m.tet_mid[i])
      if (v < 0 || static_cast<size_t>(v) >= n) bad("tetrahedron", i);
  if (!m.triangle_mid.empty() && m.triangle_mid.size() != m.triangles.size())
    throw InputError(name + ": some triangles are second order and some are not");
  if (!m.tet_mid.empty() && m.tet_mid.size() != m.tets.size())
    throw InputError(name + ": some tetrahedra are second order and some are not");
  // The triangles' mid-edge nodes would belong to no element of the volume
  // (a Medit file of TrianglesP2 and Tetrahedra read as "second order").
  if (!m.triangle_mid.empty() && !m.tets.empty() && m.tet_mid.empty())
    throw InputError(name + ": the triangles are second order and the tetrahedra first order; vdmesh reads a mesh of "
                     "one order");
  if (!m.point_size.empty() && m.point_size.size() != m.points.size())
    throw InputError(name + ": mesh sizes do not match the nodes");
  check_mid_nodes(m, name);
  for (const Vec3& p : m.points)
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
      throw InputError(name + ": a node coordinate is not a finite number");
}

void complete_triangle_mids(Mesh& m, const std::string& name) {
  if (m.tet_mid.empty() || m.tets.empty() || m.triangles.empty() || !m.triangle_mid.empty()) return;
  std::unordered_map<uint64_t, int> mid_of_edge;
  mid_of_edge.reserve(m.tets.size() * 2);
  for (size_t t = 0; t < m.tets.size(); ++t)
    for (int e = 0; e < 6; ++e)
      mid_of_edge.emplace(edge_key(m.tets[t].v[kTetEdge[e][0]], m.tets[t].v[kTetEdge[e][1]]), m.tet_mid[t][e]);
  std::vector<TriMidNodes> mids(m.triangles.size());
  for (size_t f = 0; f < m.triangles.size(); ++f)
    for (int e = 0; e < 3; ++e) {
      const int a = m.triangles[f].v[e], b = m.triangles[f].v[(e + 1) % 3];
      const auto it = mid_of_edge.find(edge_key(a, b));
      if (it == mid_of_edge.end())
        throw InputError(name + ": triangle " + std::to_string(f + 1) +
                         " is first order and an edge of it is no edge of the second-order tetrahedra, so it has "
                         "no mid-edge node");
      mids[f][e] = it->second;
    }
  m.triangle_mid = std::move(mids);
}

SurfacePoints surface_points(const Mesh& m) {
  SurfacePoints out;
  out.number.assign(m.points.size(), m.tets.empty() ? 0 : -1);
  if (m.tets.empty()) {
    out.kept.resize(m.points.size());
    for (size_t i = 0; i < m.points.size(); ++i) out.kept[i] = out.number[i] = static_cast<int>(i);
    return out;
  }
  for (const Triangle& t : m.triangles)
    for (int v : t.v) out.number[static_cast<size_t>(v)] = 0;
  for (size_t i = 0; i < m.points.size(); ++i)
    if (out.number[i] == 0) {
      out.number[i] = static_cast<int>(out.kept.size());
      out.kept.push_back(static_cast<int>(i));
    }
  return out;
}

}  // namespace vd::io::detail
