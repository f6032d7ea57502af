// Cooperative cancellation of a long run (the Python module's Ctrl-C, a GUI's
// Cancel button). The caller owns an atomic flag and passes its address in
// the options; the pipeline looks at it between phases and every few hundred
// steps of its long loops, and unwinds with CancelledError. Polling instead of
// killing a thread keeps every container and CGAL structure consistent.
#pragma once

#include <atomic>
#include "mesh/error.h"

namespace vd {

// The run was stopped through its cancel flag; no result exists. The
// command line has no flag to raise, so its code is that of a Ctrl-C.
class CancelledError : public Error {
 public:
  CancelledError() : Error("cancelled") {}
  int exit_code() const override { return 130; }
};

inline bool cancel_requested(const std::atomic<bool>* cancel) {
  return cancel != nullptr && cancel->load(std::memory_order_relaxed);
}

inline void throw_if_cancelled(const std::atomic<bool>* cancel) {
  if (cancel_requested(cancel)) throw CancelledError();
}

// For inner loops: reads the flag on every `period`-th call only (a power of
// two), so that the check costs next to nothing per step.
class CancelPoll {
 public:
  CancelPoll(const std::atomic<bool>* cancel, unsigned period) : cancel_(cancel), mask_(period - 1) {}
  void operator()() {
    if ((++calls_ & mask_) == 0) throw_if_cancelled(cancel_);
  }

 private:
  const std::atomic<bool>* cancel_;
  unsigned mask_;
  unsigned calls_ = 0;
};

}  // namespace vd
