#include "mesh/memory.h"

#include <fstream>
#include <string>

#if defined(__GLIBC__)
#include <malloc.h>
#endif

namespace vd {

namespace {

// A "Vm...:" line of /proc/self/status in MiB, 0 without it.
double status_mib(const std::string& wanted) {
  std::ifstream status("/proc/self/status");
  std::string key;
  while (status >> key) {
    if (key == wanted) {
      double kb = 0;
      status >> kb;
      return kb / 1024.0;
    }
    status.ignore(4096, '\n');
  }
  return 0;
}

}  // namespace

double peak_resident_mib() { return status_mib("VmHWM:"); }

double resident_mib() { return status_mib("VmRSS:"); }

void return_free_memory() {
#if defined(__GLIBC__)
  malloc_trim(0);
#endif
}

}  // namespace vd
