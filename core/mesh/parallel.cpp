#include "mesh/parallel.h"

namespace vd {
namespace {
std::atomic<int> requested_threads{0};
}

void set_thread_count(int threads) { requested_threads = std::max(0, threads); }

int thread_count() {
  const int n = requested_threads.load();
  if (n > 0) return n;
  return std::max(1u, std::thread::hardware_concurrency());
}

}  // namespace vd
