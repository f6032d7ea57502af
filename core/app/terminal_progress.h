// The phase line of `vdmesh mesh` on a terminal: the running phase, how far
// it has got (core/mesh/progress.h) and its seconds, redrawn in place four
// times a second; a finished phase stays as a line with its seconds.
#pragma once

#include <chrono>
#include <condition_variable>
#include <mutex>
#include <string>
#include <thread>

namespace vd::app {

class TerminalProgress {
 public:
  TerminalProgress();
  // Ends the last phase's line.
  ~TerminalProgress();
  TerminalProgress(const TerminalProgress&) = delete;
  TerminalProgress& operator=(const TerminalProgress&) = delete;

  // The pipeline's progress callback: `name` starts now.
  void phase(const std::string& name);

 private:
  void draw(bool finished);  // with mutex_ held

  std::mutex mutex_;
  std::condition_variable wake_;
  bool stop_ = false;
  std::string phase_;
  std::chrono::steady_clock::time_point started_;
  std::thread redraw_;
};

}  // namespace vd::app
