// Helpers shared by the unit tests: where the shared data is, temp files.
#pragma once

#include <gtest/gtest.h>

#include <string>

namespace vd::test {

// Folder of the shared geometry: $VDMESH_DATA, else ../shared/data beside the
// source tree.
std::string data_dir();
// Full path of a shared file, or "" when it is not there.
std::string data_file(const std::string& relative);
// A fresh path under the build's temp folder.
std::string temp_path(const std::string& name);

}  // namespace vd::test

// Skips the current test, naming the missing file, when the shared data is
// not there (a clone without ../shared). CI always has it.
#define VD_REQUIRE_DATA(var, rel)                                                  \
  const std::string var = ::vd::test::data_file(rel);                              \
  if (var.empty()) GTEST_SKIP() << "shared data not found: " << ::vd::test::data_dir() \
                                << "/" << (rel) << " (set VDMESH_DATA)"
