// libFuzzer target for one mesh reader, chosen at compile time by
// VDMESH_FUZZ_TARGET (tests/fuzz/targets.cmake lists them). Each input is
// written to a temp file with that reader's extension and read through the
// registry, so the fuzzer exercises exactly what `vdmesh` does with a file.
// Readers may throw vd::InputError; anything else (a crash, a sanitizer
// report, another exception, an out-of-range index in the result) is a bug.
//
// The "tetgen" target reads three files: the input is split at its first two
// NUL bytes into X.node, X.ele and X.face (a missing part is a missing file).
#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <string_view>

#include "converters/registry.h"
#include "mesh/error.h"

#ifndef VDMESH_FUZZ_TARGET
#error "VDMESH_FUZZ_TARGET must name the reader (see tests/fuzz/targets.cmake)"
#endif

namespace {

struct Target {
  const char* name;
  const char* extension;
};

// Keep in step with tests/fuzz/targets.cmake and make_corpus.py.
constexpr Target kTargets[] = {
    {"off", ".off"},     {"stl", ".stl"},   {"obj", ".obj"},   {"ply", ".ply"},   {"msh", ".msh"},
    {"vtk", ".vtk"},     {"vtu", ".vtu"},   {"tetgen", ".node"}, {"poly", ".poly"},
    {"smesh", ".smesh"}, {"mesh", ".mesh"}, {"meshb", ".meshb"}, {"inp", ".inp"}, {"gz", ".off.gz"},
};

constexpr const char* extension_of(const char* name) {
  for (const Target& t : kTargets) {
    const char* a = t.name;
    const char* b = name;
    while (*a && *a == *b) ++a, ++b;
    if (*a == 0 && *b == 0) return t.extension;
  }
  return nullptr;
}

constexpr const char* kExtension = extension_of(VDMESH_FUZZ_TARGET);
static_assert(kExtension != nullptr, "VDMESH_FUZZ_TARGET is not a known reader");
constexpr bool kTetgen = std::string_view(VDMESH_FUZZ_TARGET) == "tetgen";

std::string temp_base() {
  const char* dir = std::getenv("TMPDIR");
  return std::string(dir && *dir ? dir : "/tmp") + "/vdmesh-fuzz-" + VDMESH_FUZZ_TARGET + "-" +
         std::to_string(getpid());
}

void write_file(const std::string& path, std::string_view bytes) {
  FILE* f = std::fopen(path.c_str(), "wb");
  if (!f) {
    std::perror(path.c_str());
    std::abort();  // the harness cannot work; do not report a clean run
  }
  std::fwrite(bytes.data(), 1, bytes.size(), f);
  std::fclose(f);
}

// The files of one input; returns the path to read.
std::string write_input(const std::string& base, std::string_view data) {
  if (!kTetgen) {
    write_file(base + kExtension, data);
    return base + kExtension;
  }
  const char* const parts[] = {".node", ".ele", ".face"};
  for (const char* ext : parts) std::remove((base + ext).c_str());
  for (const char* ext : parts) {
    const size_t end = ext == parts[2] ? std::string_view::npos : data.find('\0');
    write_file(base + ext, data.substr(0, end));
    if (end == std::string_view::npos) break;
    data.remove_prefix(end + 1);
  }
  return base + ".node";
}

void check_indices(const vd::Mesh& m) {
  const size_t n = m.points.size();
  auto in_range = [n](int v) { return v >= 0 && static_cast<size_t>(v) < n; };
  for (const vd::Triangle& t : m.triangles)
    for (int v : t.v)
      if (!in_range(v)) __builtin_trap();
  for (const vd::Tetrahedron& t : m.tets)
    for (int v : t.v)
      if (!in_range(v)) __builtin_trap();
  for (const auto& mid : m.tet_mid)
    for (int v : mid)
      if (!in_range(v)) __builtin_trap();
  for (const auto& mid : m.triangle_mid)
    for (int v : mid)
      if (!in_range(v)) __builtin_trap();
  if (!m.tet_mid.empty() && m.tet_mid.size() != m.tets.size()) __builtin_trap();
  if (!m.triangle_mid.empty() && m.triangle_mid.size() != m.triangles.size()) __builtin_trap();
}

// Never destroyed: the exit handler below runs after static destructors.
const std::string& base_path() {
  static const std::string* base = new std::string(temp_base());
  return *base;
}

void remove_inputs() {
  for (const char* ext : {kExtension, ".ele", ".face"}) std::remove((base_path() + ext).c_str());
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  std::atexit(remove_inputs);
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string& base = base_path();
  const std::string path = write_input(base, std::string_view(reinterpret_cast<const char*>(data), size));
  try {
    check_indices(vd::io::read_mesh(path));
  } catch (const vd::InputError&) {
  }
  return 0;
}
