// In-process timer for tests/bench/bench_formats.py: reads one mesh file and
// optionally writes it, timing each step and measuring the peak resident set
// of each step separately (Linux: /proc/self/clear_refs "5" resets VmHWM).
//
//   bench_converters IN [OUT [--binary] [--msh-version 22|41]]
//
// Prints one JSON object: counts, the mesh's own size in bytes (the element
// arrays as vdmesh stores them), and per step wall and CPU seconds and peak
// RSS in bytes.
// Exit 3 on bad input, as vdmesh.
#include <time.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iostream>
#include <string>

#include "converters/registry.h"
#include "mesh/error.h"

namespace {

// VmHWM / VmRSS of this process in bytes, 0 when /proc is not there.
size_t status_bytes(const char* key) {
  std::ifstream in("/proc/self/status");
  std::string line;
  const size_t n = std::strlen(key);
  while (std::getline(in, line))
    if (line.compare(0, n, key) == 0) return std::strtoull(line.c_str() + n + 1, nullptr, 10) * 1024;
  return 0;
}

// Starts a new peak at the current resident set.
void reset_peak() { std::ofstream("/proc/self/clear_refs") << "5"; }

size_t mesh_bytes(const vd::Mesh& m) {
  return m.points.size() * sizeof(vd::Vec3) + m.tets.size() * sizeof(vd::Tetrahedron) +
         m.triangles.size() * sizeof(vd::Triangle) + m.tet_mid.size() * sizeof(vd::TetMidNodes) +
         m.triangle_mid.size() * sizeof(vd::TriMidNodes) + m.point_size.size() * sizeof(double);
}

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// CPU seconds of this process: on a shared, loaded machine the wall clock
// mostly measures the other processes.
double cpu_seconds() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

int run(int argc, char** argv) {
  if (argc < 2) {
    std::cerr << "usage: bench_converters IN [OUT [--binary] [--msh-version 22|41]]\n";
    return 2;
  }
  const std::string in = argv[1];
  const std::string out = argc > 2 ? argv[2] : "";
  vd::io::WriteOptions options;
  for (int i = 3; i < argc; ++i) {
    if (std::strcmp(argv[i], "--binary") == 0) {
      options.binary = true;
    } else if (std::strcmp(argv[i], "--msh-version") == 0 && i + 1 < argc) {
      options.msh_version = std::atoi(argv[++i]);
    } else {
      std::cerr << "bench_converters: unknown option " << argv[i] << "\n";
      return 2;
    }
  }

  const size_t rss_start = status_bytes("VmRSS:");
  reset_peak();
  auto t0 = std::chrono::steady_clock::now();
  double c0 = cpu_seconds();
  const vd::Mesh m = vd::io::read_mesh(in);
  const double read_s = seconds_since(t0);
  const double read_cpu = cpu_seconds() - c0;
  const size_t read_peak = status_bytes("VmHWM:");

  double write_s = 0, write_cpu = 0;
  size_t write_peak = 0;
  if (!out.empty()) {
    reset_peak();
    t0 = std::chrono::steady_clock::now();
    c0 = cpu_seconds();
    vd::io::write_mesh(m, out, options);
    write_s = seconds_since(t0);
    write_cpu = cpu_seconds() - c0;
    write_peak = status_bytes("VmHWM:");
  }
  std::printf(
      "{\"points\": %zu, \"tets\": %zu, \"triangles\": %zu, \"mesh_bytes\": %zu, \"rss_start\": %zu, "
      "\"read_s\": %.6f, \"read_cpu\": %.6f, \"read_peak_rss\": %zu, \"write_s\": %.6f, \"write_cpu\": %.6f, "
      "\"write_peak_rss\": %zu}\n",
      m.points.size(), m.tets.size(), m.triangles.size(), mesh_bytes(m), rss_start, read_s, read_cpu, read_peak,
      write_s, write_cpu, write_peak);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    return run(argc, argv);
  } catch (const vd::InputError& e) {
    std::cerr << e.what() << "\n";
    return 3;
  } catch (const vd::UsageError& e) {
    std::cerr << e.what() << "\n";
    return 2;
  }
}
