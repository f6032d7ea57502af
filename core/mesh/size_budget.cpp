#include "mesh/size_budget.h"

#include <unistd.h>

#include <cmath>

#include "mesh/error.h"
#include "mesh/number_text.h"

namespace vd {

namespace {

constexpr double kBytesPerTetrahedron = 120;
constexpr double kBytesPerFacet = 700;

std::string number(double x) { return number_text(x, "%.3g"); }

}  // namespace

SizeBudget size_budget(double area, double volume, double size, bool interior) {
  SizeBudget b;
  if (!(size > 0)) return b;
  b.facets = std::abs(area) / (std::sqrt(3.0) / 4.0 * size * size);
  if (interior) b.tetrahedra = std::abs(volume) / (size * size * size / (6.0 * std::sqrt(2.0)));
  b.bytes = kBytesPerTetrahedron * b.tetrahedra + kBytesPerFacet * b.facets;
  return b;
}

double physical_memory_bytes() {
  const long pages = sysconf(_SC_PHYS_PAGES), page = sysconf(_SC_PAGESIZE);
  return pages > 0 && page > 0 ? static_cast<double>(pages) * static_cast<double>(page) : 0.0;
}

void check_size_budget(double area, double volume, double size, bool interior, const std::string& what) {
  const SizeBudget b = size_budget(area, volume, size, interior);
  const double memory = physical_memory_bytes();
  if (!(memory > 0) || b.bytes <= memory) return;
  throw InputError(what + " asks for about " + number(b.facets) + " surface facets" +
                   (interior ? " and " + number(b.tetrahedra) + " tetrahedra" : std::string()) +
                   " (surface area " + number(std::abs(area)) + (interior ? ", volume " + number(std::abs(volume)) : "") +
                   "): about " + number(b.bytes / 1073741824.0) + " GiB at the " +
                   number(kBytesPerFacet) + " bytes a facet" + (interior ? " and " + number(kBytesPerTetrahedron) + " a tetrahedron" : "") +
                   " vdmesh's runs peak at, more than this machine's " + number(memory / 1073741824.0) +
                   " GiB of memory (so small a size is often a unit mix-up: millimetres against metres); choose a larger one");
}

}  // namespace vd
