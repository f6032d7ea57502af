// Errors that reach the user. Each maps to one exit code of the command line
// (README, "Exit codes"); the message names what is wrong: file and line,
// or the facet ids.
#pragma once

#include <functional>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace vd {

// Every error vdmesh throws on purpose, so that a C++ caller can catch them
// all in one place and still tell them apart from its own: `exit_code` is
// the command line's for the same failure.
class Error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
  virtual int exit_code() const = 0;
};

// Bad input: unreadable file, malformed content, invalid surface. Exit code 3.
class InputError : public Error {
 public:
  using Error::Error;
  int exit_code() const override { return 3; }
};

// A file that could not be opened, read or written, with the system's
// error number: bad input to the command line like any other (exit 3),
// and an OSError as well as an InputError to Python (errno, filename).
class FileError : public InputError {
 public:
  FileError(const std::string& message, std::string path, int error_number)
      : InputError(message), path_(std::move(path)), error_number_(error_number) {}
  const std::string& path() const { return path_; }
  int error_number() const { return error_number_; }

 private:
  std::string path_;
  int error_number_ = 0;
};

// The surface crosses itself; the crossing facet pairs (indices into the
// surface that was checked, each pair ascending), so that a caller who knows
// where the facets came from (CAD faces) can say more.
class SelfIntersectionError : public InputError {
 public:
  SelfIntersectionError(const std::string& message, std::vector<std::pair<int, int>> facet_pairs)
      : InputError(message), facet_pairs_(std::move(facet_pairs)) {}
  const std::vector<std::pair<int, int>>& facet_pairs() const { return facet_pairs_; }

 private:
  std::vector<std::pair<int, int>> facet_pairs_;
};

// Bad input shown by some facets (indices into the surface that was
// checked). `describe` words the message for a list of them, so that a
// caller that changed the surface since it was read (refinement to a size,
// recovery's splits) can name the input's facets instead.
class FacetsError : public InputError {
 public:
  using Describe = std::function<std::string(const std::vector<int>& facets)>;
  FacetsError(Describe describe, std::vector<int> facets)
      : InputError(describe(facets)), describe_(std::move(describe)), facets_(std::move(facets)) {}
  const std::vector<int>& facets() const { return facets_; }
  std::string describe(const std::vector<int>& facets) const { return describe_(facets); }

 private:
  Describe describe_;
  std::vector<int> facets_;
};

// Some facets could not be made Delaunay within the guards. Exit code 4.
// `faces`: the face ids of the facets still missing, ascending, so that a
// caller who can tessellate again (CAD input) knows where recovery ran away.
class RecoveryError : public Error {
 public:
  explicit RecoveryError(const std::string& message, std::vector<int> faces = {}, bool ran_away = false)
      : Error(message), faces_(std::move(faces)), ran_away_(ran_away) {}
  int exit_code() const override { return 4; }
  const std::vector<int>& faces() const { return faces_; }
  // Stopped because the missing facets grew far past where they started.
  bool ran_away() const { return ran_away_; }

 private:
  std::vector<int> faces_;
  bool ran_away_ = false;
};

// Bad command-line use. Exit code 2.
class UsageError : public Error {
 public:
  using Error::Error;
  int exit_code() const override { return 2; }
};

}  // namespace vd
