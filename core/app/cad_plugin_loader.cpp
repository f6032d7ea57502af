#include "app/cad_plugin_loader.h"

#include <dlfcn.h>

#include <filesystem>
#include <stdexcept>
#include <string>

#include "cad/header_fingerprint.h"

namespace vd::app {

const cad::CadEntryPoints& cad_plugin() {
  static const cad::CadEntryPoints* entry = nullptr;
  if (entry) return *entry;
  std::error_code ec;
  const std::filesystem::path program = std::filesystem::read_symlink("/proc/self/exe", ec);
  if (ec) throw std::runtime_error("CAD input: cannot find the program's own folder (/proc/self/exe)");
  const std::string path = (program.parent_path() / ".." / "lib" / "vdmesh" / "libvdmesh_cad.so").lexically_normal();
  // RTLD_NOW: a missing symbol is found here, not in the middle of a run.
  // The handle stays open to the end of the program.
  void* handle = dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
  if (!handle) throw std::runtime_error(std::string("CAD input needs the CAD plugin: ") + dlerror());
  using Entry = const cad::CadEntryPoints* (*)();
  auto find = reinterpret_cast<Entry>(dlsym(handle, "vdmesh_cad_entry_points"));
  if (!find) throw std::runtime_error("CAD input: " + path + " has no vdmesh_cad_entry_points");
  const cad::CadEntryPoints* found = find();
  if (found->abi != cad::kCadPluginAbi)
    throw std::runtime_error("CAD input: " + path + " is of another build (interface " + std::to_string(found->abi) +
                             ", the program's " + std::to_string(cad::kCadPluginAbi) + ")");
  if (std::string(found->header_fingerprint) != kCoreHeaderFingerprint)
    throw std::runtime_error("CAD input: " + path +
                             " is of another build (built against other core headers than the program); "
                             "install the program and lib/vdmesh/libvdmesh_cad.so of one build together");
  entry = found;
  return *entry;
}

}  // namespace vd::app
