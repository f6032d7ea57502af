// The subcommands of the `vdmesh` program. Each takes its arguments (after
// the subcommand name) and returns the exit code (README, "Exit codes").
#pragma once

#include <string>
#include <vector>

namespace vd::app {

int mesh_command(const std::vector<std::string>& args);
int convert_command(const std::vector<std::string>& args);
int info_command(const std::vector<std::string>& args);
int compare_command(const std::vector<std::string>& args);  // app/compare_command.cpp
// `vdmesh --version`: vdmesh's and its libraries' versions; whether CAD input works.
int version_command();

}  // namespace vd::app
