// Loops over independent items on several threads. The range is cut into
// chunks of a fixed size whatever the number of threads, and callers combine
// per-chunk results in chunk order, so a sum of floating-point numbers (and
// everything else) comes out the same on one thread or on many.
#pragma once

#include <algorithm>
#include <atomic>
#include <exception>
#include <mutex>
#include <thread>
#include <vector>

namespace vd {

// Threads the loops below may use; 0 (the default) means one per core.
void set_thread_count(int threads);
int thread_count();

// Calls body(chunk, begin, end) for the chunks [chunk * size, ...) of [0, n),
// each once, on up to thread_count() threads (up to `threads` when that is
// given, > 0). The first exception a body throws is rethrown here after
// every thread has stopped.
template <class Body>
void for_each_chunk(long n, long chunk_size, Body body, int threads = 0) {
  const long chunks = n <= 0 ? 0 : (n + chunk_size - 1) / chunk_size;
  const long workers = std::min<long>(threads > 0 ? threads : thread_count(), chunks);
  if (workers <= 1) {
    for (long c = 0; c < chunks; ++c) body(c, c * chunk_size, std::min(n, (c + 1) * chunk_size));
    return;
  }
  std::atomic<long> next{0};
  std::exception_ptr failure;
  std::mutex failure_lock;
  auto work = [&] {
    for (long c; (c = next.fetch_add(1)) < chunks;) {
      try {
        body(c, c * chunk_size, std::min(n, (c + 1) * chunk_size));
      } catch (...) {
        std::lock_guard<std::mutex> hold(failure_lock);
        if (!failure) failure = std::current_exception();
        next = chunks;  // the others stop at their next chunk
      }
    }
  };
  std::vector<std::thread> pool;
  for (long w = 1; w < workers; ++w) pool.emplace_back(work);
  work();
  for (std::thread& t : pool) t.join();
  if (failure) std::rethrow_exception(failure);
}

}  // namespace vd
