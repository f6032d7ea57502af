// The process's memory: its high-water mark.
#pragma once

namespace vd {

// The high-water mark of resident memory in MiB, from /proc/self/status
// (VmHWM); 0 where that file does not exist.
double peak_resident_mib();

}  // namespace vd
