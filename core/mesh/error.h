// Errors that reach the user. Each maps to one exit code of the command line
// (README, "Exit codes"); the message names what is wrong: file and line,
// or the facet ids.
#pragma once

#include <stdexcept>
#include <string>

namespace vd {

// Bad input: unreadable file, malformed content, invalid surface. Exit code 3.
class InputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Some facets could not be made Delaunay within the guards. Exit code 4.
class RecoveryError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Bad command-line use. Exit code 2.
class UsageError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace vd
