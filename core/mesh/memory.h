// The process's memory: its high-water mark and what it holds now, and
// giving freed heap back.
#pragma once

namespace vd {

// The high-water mark of resident memory in MiB, from /proc/self/status
// (VmHWM); 0 where that file does not exist.
double peak_resident_mib();

// Resident memory now in MiB (VmRSS), 0 where that file does not exist.
double resident_mib();

// Hands the heap's free pages back to the system (glibc's malloc_trim; a
// no-op elsewhere). Freed blocks inside the heap stay resident otherwise, and
// whatever is allocated next may take new pages beside them; handed back,
// each page taken again costs a page fault.
void return_free_memory();

}  // namespace vd
