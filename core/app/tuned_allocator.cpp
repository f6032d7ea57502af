#include "app/tuned_allocator.h"

#include <cstdlib>

#if defined(__GLIBC__)
#include <unistd.h>
#endif

namespace vd::app {

namespace {

// hugetlb=1: malloc asks for transparent huge pages (madvise) on the memory
// it takes from the system. mmap_threshold (the largest glibc accepts) and
// trim_threshold: blocks stay in the heap, freed memory is reused instead
// of unmapped and faulted in again (a page fault costs about 20 us on the
// 2-CPU VMs this was measured on). The number of arenas stays glibc's: one
// arena for all threads (arena_max=1) saved Nefertiti's surface run 14 MiB
// of thread heaps but cost gmsh_simple_plane.brep 2 to 4 s of 22 in lock
// waits (OpenCASCADE's fuse and the faces remeshed on two threads allocate
// a lot), 27.0 / 25.0 s against 22.8 / 22.2 s.
constexpr const char* kTunables =
    "glibc.malloc.hugetlb=1:glibc.malloc.mmap_threshold=33554432:glibc.malloc.trim_threshold=4294967295";
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
