#include "app/terminal_progress.h"

#include <cstdio>

#include "mesh/progress.h"

namespace vd::app {

TerminalProgress::TerminalProgress()
    : redraw_([this] {
        std::unique_lock<std::mutex> lock(mutex_);
        while (!wake_.wait_for(lock, std::chrono::milliseconds(250), [this] { return stop_; }))
          if (!phase_.empty()) draw(false);
      }) {}

TerminalProgress::~TerminalProgress() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (!phase_.empty()) draw(true);
    stop_ = true;
  }
  wake_.notify_all();
  redraw_.join();
}

void TerminalProgress::phase(const std::string& name) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (!phase_.empty()) draw(true);
  clear_phase_fraction();  // the CAD phases do not go through the pipeline's timer
  phase_ = name;
  started_ = std::chrono::steady_clock::now();
  draw(false);
}

void TerminalProgress::draw(bool finished) {
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - started_).count();
  const double done = phase_fraction();
  // \r and "erase to the end of the line": the line is drawn over itself.
  if (finished)
    std::fprintf(stderr, "\r\033[Kvdmesh: %s %.2f s\n", phase_.c_str(), seconds);
  else if (done >= 0)
    std::fprintf(stderr, "\r\033[Kvdmesh: %s %3.0f %% %.1f s", phase_.c_str(), 100 * done, seconds);
  else
    std::fprintf(stderr, "\r\033[Kvdmesh: %s... %.1f s", phase_.c_str(), seconds);
  std::fflush(stderr);
}

}  // namespace vd::app
