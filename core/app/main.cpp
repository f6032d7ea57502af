// vdmesh: the command-line tool. Exit codes: 0 done; 1 internal error;
// 2 usage; 3 bad input; 4 some facets could not be recovered; 128 + N
// stopped by signal N (compare, which has children and a work folder).
#include <cstdio>
#include <exception>
#include <string>
#include <vector>

#include "app/commands.h"
#include "app/tuned_allocator.h"
#include "compare/child_process.h"
#include "mesh/error.h"

namespace {

const char* kUsage =
    "usage:\n"
    "  vdmesh mesh INPUT -o OUTPUT [options]   tetrahedra of a closed tagged surface\n"
    "  vdmesh convert IN OUT [--binary] [--msh-version 22|41] [--from FMT] [--to FMT]\n"
    "  vdmesh info MESH                         counts, regions, faces, quality\n"
    "  vdmesh compare INPUT [--size H] [--json OUT.json] [--svg OUT.svg]   vdmesh and TetGen side by side\n"
    "  vdmesh --version                         versions of vdmesh and of the libraries it runs on\n"
    "run 'vdmesh mesh --help' for the meshing options\n";

}  // namespace

int main(int argc, char** argv) {
  vd::app::run_with_tuned_allocator(argv);
  std::vector<std::string> args(argv + 1, argv + argc);
  if (args.empty() || args[0] == "-h" || args[0] == "--help") {
    std::fputs(kUsage, args.empty() ? stderr : stdout);
    return args.empty() ? 2 : 0;
  }
  if (args[0] == "--version" || args[0] == "version") return vd::app::version_command();
  const std::string command = args[0];
  args.erase(args.begin());
  try {
    if (command == "mesh") return vd::app::mesh_command(args);
    if (command == "convert") return vd::app::convert_command(args);
    if (command == "info") return vd::app::info_command(args);
    if (command == "compare") return vd::app::compare_command(args);
    std::fprintf(stderr, "vdmesh: unknown command '%s'\n%s", command.c_str(), kUsage);
    return 2;
  } catch (const vd::UsageError& e) {
    std::fprintf(stderr, "vdmesh %s: %s\n", command.c_str(), e.what());
    return 2;
  } catch (const vd::InputError& e) {
    std::fprintf(stderr, "vdmesh %s: bad input: %s\n", command.c_str(), e.what());
    return 3;
  } catch (const vd::RecoveryError& e) {
    std::fprintf(stderr, "vdmesh %s: %s\n", command.c_str(), e.what());
    return 4;
  } catch (const vd::compare::Stopped& e) {
    // A Ctrl-C or kill: the children are gone and the work folder with them.
    std::fprintf(stderr, "vdmesh %s: %s\n", command.c_str(), e.what());
    return 128 + e.signal();
  } catch (const std::bad_alloc&) {
    std::fprintf(stderr, "vdmesh %s: out of memory\n", command.c_str());
    return 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "vdmesh %s: internal error: %s\n", command.c_str(), e.what());
    return 1;
  }
}
