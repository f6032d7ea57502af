#include "mesh/progress.h"

#include <algorithm>
#include <atomic>

namespace vd {
namespace {
std::atomic<double> g_fraction{-1.0};
}

void set_phase_fraction(double done) { g_fraction.store(std::clamp(done, 0.0, 1.0), std::memory_order_relaxed); }

void clear_phase_fraction() { g_fraction.store(-1.0, std::memory_order_relaxed); }

double phase_fraction() { return g_fraction.load(std::memory_order_relaxed); }

}  // namespace vd
