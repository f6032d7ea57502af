// glibc's allocator, set up for meshing: huge pages, freed memory kept.
#pragma once

namespace vd::app {

// Runs this program again, once, with glibc's malloc tunables set for
// meshing, and returns only when it did not (another C library, a sanitizer
// build, GLIBC_TUNABLES already set by the user, or exec failing). In the
// second run it clears what it set, so children (TetGen under `compare`)
// get the caller's environment. Why: on this machine's VM a first touch of a
// 4 KiB page costs several microseconds, and a surface run of 100k facets
// took 24,600 of them (a fifth of its time in the kernel); with
// transparent huge pages on the heap and freed memory kept for reuse, about
// a thousand. glibc reads its tunables only when the program is
// loaded, hence the second run.
void run_with_tuned_allocator(char** argv);

// "tuned" when this run is the second one, with the tunables above; "as
// given" otherwise. For the report, so a benchmark says which it measured.
const char* allocator_in_use();

}  // namespace vd::app
