#include "compare/child_process.h"

#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <chrono>
#include <condition_variable>
#include <cstring>
#include <fstream>
#include <iterator>
#include <mutex>
#include <sstream>
#include <thread>

extern char** environ;

namespace vd::compare {

std::string ChildResult::status() const {
  if (!started) return "not started: " + error;
  std::ostringstream s;
  if (timed_out) {
    s << "timed out after " << wall_seconds << " s";
  } else if (signal != 0) {
    s << "killed by signal " << signal << " (" << strsignal(signal) << ")";
  } else {
    s << "exit " << exit_code;
  }
  return s.str();
}

namespace {

// Written by the signal handler: a lock-free atomic and a sig_atomic_t are
// what a handler may touch.
std::atomic<pid_t> running_child{0};
volatile sig_atomic_t stop_signal = 0;
static_assert(std::atomic<pid_t>::is_always_lock_free, "the signal handler reads the child's pid");

void on_stop_signal(int sig) {
  stop_signal = sig;
  const pid_t child = running_child.load();
  if (child > 0) kill(-child, SIGKILL);
}

}  // namespace

void stop_children_on_signals() {
  struct sigaction sa;
  std::memset(&sa, 0, sizeof sa);
  sa.sa_handler = on_stop_signal;
  sigemptyset(&sa.sa_mask);
  for (int sig : {SIGINT, SIGTERM, SIGHUP}) sigaction(sig, &sa, nullptr);
}

Stopped::Stopped(int signal)
    : std::runtime_error("stopped by signal " + std::to_string(signal) + " (" + strsignal(signal) + ")"),
      signal_(signal) {}

void throw_if_stopped() {
  if (stop_signal != 0) throw Stopped(stop_signal);
}

ChildResult run_child(const std::vector<std::string>& argv, const std::string& log_path, double timeout_seconds) {
  ChildResult r;
  throw_if_stopped();
  if (argv.empty()) {
    r.error = "no program";
    return r;
  }
  std::vector<char*> args;
  for (const auto& a : argv) args.push_back(const_cast<char*>(a.c_str()));
  args.push_back(nullptr);

  posix_spawn_file_actions_t actions;
  posix_spawnattr_t attr;
  posix_spawn_file_actions_init(&actions);
  posix_spawnattr_init(&attr);
  posix_spawn_file_actions_addopen(&actions, STDIN_FILENO, "/dev/null", O_RDONLY, 0);
  posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, log_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_adddup2(&actions, STDOUT_FILENO, STDERR_FILENO);
  // Own process group: a timeout kills whatever the child started too.
  posix_spawnattr_setpgroup(&attr, 0);
  posix_spawnattr_setflags(&attr, POSIX_SPAWN_SETPGROUP);

  const auto t0 = std::chrono::steady_clock::now();
  pid_t pid = 0;
  const int rc = argv[0].find('/') == std::string::npos
                     ? posix_spawnp(&pid, args[0], &actions, &attr, args.data(), environ)
                     : posix_spawn(&pid, args[0], &actions, &attr, args.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  posix_spawnattr_destroy(&attr);
  if (rc != 0) {
    r.error = argv[0] + ": " + std::strerror(rc);
    return r;
  }
  r.started = true;
  running_child = pid;
  // A signal between the spawn and the line above found no child to kill.
  if (stop_signal != 0) kill(-pid, SIGKILL);

  // A watchdog kills the group at the time limit. The child is waited for
  // without being reaped first (WNOWAIT), so its pid and group cannot be
  // reused before the watchdog has stood down.
  std::mutex mutex;
  std::condition_variable cv;
  bool ended = false, killed = false;
  std::thread watchdog;
  if (timeout_seconds > 0)
    watchdog = std::thread([&] {
      std::unique_lock<std::mutex> lock(mutex);
      if (!cv.wait_for(lock, std::chrono::duration<double>(timeout_seconds), [&] { return ended; })) {
        killed = true;
        kill(-pid, SIGKILL);
      }
    });
  siginfo_t info;
  while (waitid(P_PID, static_cast<id_t>(pid), &info, WEXITED | WNOWAIT) != 0 && errno == EINTR) {
  }
  r.wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  {
    std::lock_guard<std::mutex> lock(mutex);
    ended = true;
  }
  cv.notify_all();
  if (watchdog.joinable()) watchdog.join();

  int status = 0;
  struct rusage ru;
  std::memset(&ru, 0, sizeof ru);
  while (wait4(pid, &status, 0, &ru) < 0 && errno == EINTR) {
  }
  running_child = 0;
  r.cpu_seconds = ru.ru_utime.tv_sec + ru.ru_utime.tv_usec * 1e-6 + ru.ru_stime.tv_sec + ru.ru_stime.tv_usec * 1e-6;
  r.peak_rss_mib = ru.ru_maxrss / 1024.0;  // KiB on Linux
  if (WIFEXITED(status)) r.exit_code = WEXITSTATUS(status);
  if (WIFSIGNALED(status)) r.signal = WTERMSIG(status);
  r.timed_out = killed;
  return r;
}

std::string tail_of_file(const std::string& path, int max_lines) {
  std::ifstream f(path, std::ios::binary);
  if (!f) return "";
  f.seekg(0, std::ios::end);
  const std::streamoff size = f.tellg();
  const std::streamoff from = size > 8192 ? size - 8192 : 0;
  f.seekg(from);
  std::string text((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
  while (!text.empty() && (text.back() == '\n' || text.back() == '\r' || text.back() == ' ')) text.pop_back();
  // Start of the last `max_lines` lines: after the max_lines-th newline from the end.
  size_t start = 0;
  size_t pos = text.size();
  for (int n = 0; n < max_lines; ++n) {
    const size_t nl = pos == 0 ? std::string::npos : text.rfind('\n', pos - 1);
    if (nl == std::string::npos) {
      start = 0;
      break;
    }
    start = nl + 1;
    pos = nl;
  }
  return text.substr(start);
}

std::string failure_text(const ChildResult& r, const std::string& log_path, int max_lines) {
  std::string text = r.status();
  std::string tail = tail_of_file(log_path, max_lines);
  if (tail.empty()) return text;
  std::string joined;
  for (char c : tail) {
    if (c == '\r') continue;
    if (c == '\n') joined += " | ";
    else joined += c;
  }
  return text + ": " + joined;
}

std::string self_executable() {
  char buf[4096];
  const ssize_t n = readlink("/proc/self/exe", buf, sizeof buf - 1);
  if (n <= 0) return "";
  buf[n] = '\0';
  return buf;
}

}  // namespace vd::compare
