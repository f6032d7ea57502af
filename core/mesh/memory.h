// The process's memory: its high-water mark, and giving freed heap back.
#pragma once

namespace vd {

// The high-water mark of resident memory in MiB, from /proc/self/status
// (VmHWM); 0 where that file does not exist.
double peak_resident_mib();

// Hands the heap's free pages back to the system (glibc's malloc_trim; a
// no-op elsewhere). Freed blocks inside the heap stay resident otherwise, and
// whatever is allocated next takes new pages beside them: the sliver pass's
// complex, built after the tetrahedralization is freed, stacked on top of it.
void return_free_memory();

}  // namespace vd
