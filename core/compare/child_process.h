// Runs a program in a separate process with a time limit, and measures it:
// wall-clock time, CPU time and peak resident memory (wait4's rusage). A
// crash, abort or timeout of the child is a result, never an exception, so a
// failing third-party mesher cannot take `vdmesh compare` down.
#pragma once

#include <stdexcept>
#include <string>
#include <vector>

namespace vd::compare {

struct ChildResult {
  bool started = false;     // false: the program could not be started (see error)
  bool timed_out = false;   // killed (SIGKILL) at the time limit
  int exit_code = -1;       // when it exited by itself
  int signal = 0;           // when a signal ended it
  double wall_seconds = 0;  // from spawn to exit
  double cpu_seconds = 0;   // user + system of the child
  double peak_rss_mib = 0;  // ru_maxrss of the child
  std::string error;        // why it could not be started
  bool ok() const { return started && !timed_out && signal == 0 && exit_code == 0; }
  // "exit 0", "exit 3", "killed by signal 6 (Aborted)", "timed out after 5 s", ...
  std::string status() const;
};

// Runs argv[0] (searched in PATH when it has no '/') with argv, in its own
// process group, stdout and stderr both written to `log_path`. At
// `timeout_seconds` (> 0) the group is killed. Blocks until the child ends.
ChildResult run_child(const std::vector<std::string>& argv, const std::string& log_path, double timeout_seconds);

// The last `max_lines` lines of a text file (empty when it cannot be read).
std::string tail_of_file(const std::string& path, int max_lines = 6);

// "status: the last lines | of the log" for a failed run.
std::string failure_text(const ChildResult& r, const std::string& log_path, int max_lines = 4);

// SIGINT, SIGTERM and SIGHUP from now on kill the running child's process
// group at once and are remembered; the caller stops at its next
// throw_if_stopped() and unwinds, so its temporary files go too. Without
// this a Ctrl-C left TetGen running in its own group and the work folder
// behind.
void stop_children_on_signals();

// Thrown by throw_if_stopped() once one of those signals came.
class Stopped : public std::runtime_error {
 public:
  explicit Stopped(int signal);
  int signal() const { return signal_; }

 private:
  int signal_;
};
void throw_if_stopped();

// This program's own executable (/proc/self/exe), to run a part of it in a
// child process.
std::string self_executable();

}  // namespace vd::compare
