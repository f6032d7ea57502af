#include "test_support.h"

#include <cmath>
#include <cstdlib>
#include <filesystem>

#include "delaunay/delaunay_tetrahedralization.h"
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

Mesh thin_wedge(double deg) {
  Mesh in;
  const double h = std::sin(deg * M_PI / 180.0);
  in.points = {{0, 0, 0}, {0, 1, 0}, {1, 0, 0}, {1, 1, 0}, {1, 0, h}, {1, 1, h}};
  // Regions front/back as the conventions say: region 1 behind each facet.
  auto quad = [&](int a, int b, int c, int d, int face) {
    in.triangles.push_back({{a, b, c}, face, 0, 1});
    in.triangles.push_back({{a, c, d}, face, 0, 1});
  };
  quad(0, 1, 3, 2, 1);  // bottom, normal -z
  quad(0, 4, 5, 1, 2);  // top
  in.triangles.push_back({{0, 2, 4}, 3, 0, 1});  // y = 0
  in.triangles.push_back({{1, 5, 3}, 4, 0, 1});  // y = 1
  quad(2, 3, 5, 4, 5);  // x = 1
  return in;
}

int facets_missing_from_fresh_dt(const Mesh& m) {
  DelaunayTetrahedralization dt;
  dt.insert(m.points);
  int missing = 0;
  for (const Triangle& t : m.triangles) missing += !dt.has_facet(t.v[0], t.v[1], t.v[2]);
  return missing;
}

}  // namespace vd::test
