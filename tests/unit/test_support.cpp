#include "test_support.h"

#include <cstdlib>
#include <filesystem>

#include "mesh/shapes.h"

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

Mesh two_boxes_sharing_a_face(int n) {
  Mesh m = shapes::box({0, 0, 0}, {1, 1, 1}, n, 1, 1);
  shapes::append(m, shapes::box({1, 0, 0}, {2, 1, 1}, n, 2, 7));
  shapes::weld_exact(m);
  shapes::merge_coincident_facets(m);
  return m;
}

Mesh box_in_box() {
  Mesh m = shapes::box({0, 0, 0}, {3, 3, 3}, 3, 1, 1);
  Mesh inner = shapes::box({1, 1, 1}, {2, 2, 2}, 2, 2, 7);
  for (Triangle& t : inner.triangles) t.front = 1;  // region 2 inside region 1
  shapes::append(m, inner);
  return m;
}

}  // namespace vd::test
