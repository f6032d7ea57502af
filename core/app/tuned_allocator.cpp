#include "app/tuned_allocator.h"

#include <cstdlib>

#if defined(__GLIBC__)
#include <unistd.h>
#endif

namespace vd::app {

namespace {

// hugetlb=1: malloc asks for transparent huge pages (madvise) on the memory
// it takes from the system. arena_max=1: one heap for all threads; worker
// threads each touching their own heap cost a huge page apiece, and our
// threads allocate little. mmap_threshold (the largest glibc accepts) and
// trim_threshold: blocks stay in the heap, freed memory is reused instead
// of unmapped and faulted in again (return_free_memory() still trims it
// where a phase wants it back).
constexpr const char* kTunables =
    "glibc.malloc.hugetlb=1:glibc.malloc.arena_max=1:"
    "glibc.malloc.mmap_threshold=33554432:glibc.malloc.trim_threshold=4294967295";
constexpr const char* kMarker = "VDMESH_TUNED_ALLOCATOR";

bool tuned = false;

bool sanitized() {
#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
  return true;
#else
  return false;
#endif
}

}  // namespace

void run_with_tuned_allocator(char** argv) {
#if defined(__GLIBC__)
  if (std::getenv(kMarker) != nullptr) {
    unsetenv(kMarker);
    unsetenv("GLIBC_TUNABLES");
    tuned = true;
    return;
  }
  if (sanitized() || std::getenv("GLIBC_TUNABLES") != nullptr) return;
  if (setenv("GLIBC_TUNABLES", kTunables, 1) != 0 || setenv(kMarker, "1", 1) != 0) return;
  execv("/proc/self/exe", argv);
  // exec failed (no /proc, say): go on with the allocator as it is.
  unsetenv(kMarker);
  unsetenv("GLIBC_TUNABLES");
#else
  (void)argv;
#endif
}

const char* allocator_in_use() { return tuned ? "tuned" : "as given"; }

}  // namespace vd::app
