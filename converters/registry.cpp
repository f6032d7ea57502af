#include "registry.h"

#include "formats/formats.h"
#include "formats/io_util.h"
#include "mesh/error.h"

namespace vd::io {

const std::vector<Format>& formats() {
  static const std::vector<Format> all = {
      make_gmsh_format(),   make_vtu_format(),   make_pvtu_format(), make_vtk_format(),
      make_abaqus_format(), make_medit_format(), make_meshb_format(), make_tetgen_format(),
      make_tetgen_plc_format(), make_off_format(), make_stl_format(),
      make_obj_format(),    make_ply_format(),
  };
  return all;
}

const Format& format_for(const std::string& path, const std::string& format_name) {
  if (!format_name.empty()) {
    for (const Format& f : formats())
      if (detail::iequals(f.name, format_name)) return f;
    std::string known;
    for (const Format& f : formats()) known += (known.empty() ? "" : ", ") + f.name;
    throw UsageError("unknown mesh format '" + format_name + "' (known: " + known + ")");
  }
  const std::string ext = detail::extension_of(path);
  for (const Format& f : formats())
    for (const std::string& e : f.extensions)
      if (e == ext) return f;
  std::string known;
  for (const Format& f : formats())
    for (const std::string& e : f.extensions) known += (known.empty() ? "" : " ") + e;
  throw UsageError(path + ": unknown mesh file extension '" + ext + "' (known: " + known +
                   ", each optionally .gz)");
}

Mesh read_mesh(const std::string& path, const std::string& format_name) {
  const Format& f = format_for(path, format_name);
  Mesh m = f.read(path);
  detail::complete_triangle_mids(m, path);
  detail::require_valid(m, path);
  return m;
}

void write_mesh(const Mesh& mesh, const std::string& path, const WriteOptions& options,
                const std::string& format_name) {
  const Format& f = format_for(path, format_name);
  if (!f.write) throw UsageError(path + ": the " + f.name + " format can only be read");
  if (options.msh_version != 22 && options.msh_version != 41)
    throw UsageError("Gmsh version must be 22 or 41, not " + std::to_string(options.msh_version));
  // The writers trust the arrays: a node number past the points or a short
  // mid-edge list was read past from C++ and written out (2026-11-30).
  detail::require_valid(mesh, path);
  f.write(mesh, path, options);
}

}  // namespace vd::io
