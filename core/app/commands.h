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

}  // namespace vd::app
