#include "test_support.h"

#include <cstdlib>
#include <filesystem>

namespace vd::test {

std::string data_dir() {
  if (const char* env = std::getenv("VDMESH_DATA"); env && *env) return env;
  return VDMESH_DEFAULT_DATA;
}

std::string data_file(const std::string& relative) {
  const std::filesystem::path p = std::filesystem::path(data_dir()) / relative;
  return std::filesystem::exists(p) ? p.string() : std::string();
}

std::string temp_path(const std::string& name) {
  const auto dir = std::filesystem::temp_directory_path() / "vdmesh-tests";
  std::filesystem::create_directories(dir);
  const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
  std::string prefix = info ? std::string(info->test_suite_name()) + "." + info->name() + "." : "";
  return (dir / (prefix + name)).string();
}

}  // namespace vd::test
