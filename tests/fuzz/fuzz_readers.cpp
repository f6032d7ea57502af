// libFuzzer target for every mesh reader. The first byte of an input picks
// the file extension (so one corpus covers all formats and each entry keeps
// its format); the rest is written to a temp file and read. Readers may
// throw vd::InputError; anything else (a crash, a sanitizer report, another
// exception) is a bug.
#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "converters/registry.h"
#include "mesh/error.h"

namespace {

// Keep in step with tests/fuzz/make_corpus.py.
const char* const kExtensions[] = {".off", ".stl", ".obj", ".msh", ".vtk", ".vtu",
                                   ".node", ".poly", ".smesh", ".mesh", ".inp", ".off.gz"};
constexpr size_t kCount = sizeof kExtensions / sizeof kExtensions[0];

std::string temp_base() {
  const char* dir = std::getenv("TMPDIR");
  return std::string(dir && *dir ? dir : "/tmp") + "/vdmesh-fuzz-" + std::to_string(getpid());
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size == 0) return 0;
  static const std::string base = temp_base();
  const std::string path = base + kExtensions[data[0] % kCount];
  FILE* f = std::fopen(path.c_str(), "wb");
  if (!f) return 0;
  std::fwrite(data + 1, 1, size - 1, f);
  std::fclose(f);
  try {
    const vd::Mesh m = vd::io::read_mesh(path);
    // What a reader returns must be usable: every index in range.
    for (const vd::Triangle& t : m.triangles)
      for (int v : t.v)
        if (v < 0 || static_cast<size_t>(v) >= m.points.size()) __builtin_trap();
    for (const vd::Tetrahedron& t : m.tets)
      for (int v : t.v)
        if (v < 0 || static_cast<size_t>(v) >= m.points.size()) __builtin_trap();
  } catch (const vd::InputError&) {
  }
  std::remove(path.c_str());
  return 0;
}
