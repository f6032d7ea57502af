// One reader and one writer per mesh format, found by file extension (or by an
// explicit format name for ambiguous cases). The command line and the Python
// module read and write every file through here.
#pragma once

#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "mesh/mesh.h"

namespace vd::io {

struct WriteOptions {
  bool binary = false;      // formats that have a binary variant
  int msh_version = 41;     // Gmsh: 22 or 41
};

struct Format {
  std::string name;                     // "gmsh", "vtu", "off", ...
  std::vector<std::string> extensions;  // lower case, with the dot: ".msh"
  bool holds_volume = false;            // can carry tetrahedra
  // Throws vd::InputError naming the file and the line (or byte offset).
  std::function<Mesh(const std::string& path)> read;
  // Empty when the format is read-only.
  std::function<void(const Mesh&, const std::string& path, const WriteOptions&)> write;
  // Formats of several files (TetGen's): every file a write to `path`
  // replaces, those it does not write removed. Empty: the one file.
  std::function<std::vector<std::string>(const std::string& path)> set_files;
};

// Every registered format.
const std::vector<Format>& formats();

// The format for `path` by its extension (".gz" is looked through), or by
// `format_name` when not empty. Throws vd::UsageError when none fits.
const Format& format_for(const std::string& path, const std::string& format_name = "");

// Where a file written to `path` goes. A symlink's target is written, not
// the link replaced; what is there and no regular file (a FIFO, a device)
// is written in place; a regular file replaced keeps its permissions. Until
// 2026-11-30 a link, /dev/full or a FIFO became a plain file and a 0600 file
// 0644. (A hard link's other names keep the old file: the new one is
// renamed into place, so that a failed write leaves the old one whole.)
struct WriteTarget {
  std::string path;
  bool in_place = false;
  std::optional<std::filesystem::perms> perms;  // of the regular file replaced
};
WriteTarget write_target(const std::string& path);

// Removes what writes of `path` by processes that no longer run left beside
// it (PATH.part.<pid>.*, files or folders): each write has a part of its
// own, which a killed run (SIGKILL, Ctrl-C) leaves, and nothing else would
// remove them.
void remove_stale_parts(const std::string& path);

Mesh read_mesh(const std::string& path, const std::string& format_name = "");
void write_mesh(const Mesh& mesh, const std::string& path, const WriteOptions& options = {},
                const std::string& format_name = "");

}  // namespace vd::io
