// Will a run at a given size fit in this machine's memory? Asked before
// anything is refined: `--size 1e-9` on a unit box went on splitting edges
// until the kernel killed the process at 23.6 GB, where a wrong unit should
// get an error that names the size.
#pragma once

#include <string>

namespace vd {

struct SizeBudget {
  double facets = 0;      // surface facets at that size (equilateral, edge = size)
  double tetrahedra = 0;  // tetrahedra in the enclosed volume (regular, edge = size); 0 without interior
  double bytes = 0;       // what a run peaks at for those
};

// Estimates from the surface's area and the volume it encloses. The bytes
// per element are what vdmesh's runs peak at (2026-11-26: 119 a tetrahedron
// on the 5.4M box, 700 a facet on surface-only runs of 89k to 100k facets).
SizeBudget size_budget(double area, double volume, double size, bool interior);

// The machine's physical memory in bytes (0 when unknown).
double physical_memory_bytes();

// Throws InputError naming the size, the estimates and the memory when the
// estimate is over the physical memory. `what`: how the size was set
// ("--size 1e-09").
void check_size_budget(double area, double volume, double size, bool interior, const std::string& what);

}  // namespace vd
