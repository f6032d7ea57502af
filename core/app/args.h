// The command line of each vdmesh command: flags with values, flags without,
// then positionals (an option left over is a usage error).
#pragma once

#include <algorithm>
#include <charconv>
#include <cmath>
#include <string>
#include <vector>

#include "mesh/error.h"

namespace vd::app {

class Args {
 public:
  explicit Args(std::vector<std::string> a) : a_(std::move(a)) {}
  bool flag(const std::string& name) {
    for (size_t i = 0; i < a_.size(); ++i)
      if (a_[i] == name) {
        a_.erase(a_.begin() + static_cast<long>(i));
        return true;
      }
    return false;
  }
  // Is `name` on the line (not consumed)?
  bool has(const std::string& name) const { return std::find(a_.begin(), a_.end(), name) != a_.end(); }
  std::string value(const std::string& name, const std::string& fallback = "") {
    for (size_t i = 0; i < a_.size(); ++i)
      if (a_[i] == name) {
        if (i + 1 >= a_.size()) throw UsageError(name + " needs a value");
        std::string v = a_[i + 1];
        a_.erase(a_.begin() + static_cast<long>(i), a_.begin() + static_cast<long>(i) + 2);
        return v;
      }
    return fallback;
  }
  double number(const std::string& name, double fallback) {
    const std::string v = value(name);
    if (v.empty()) return fallback;
    double x = 0;
    auto [ptr, ec] = std::from_chars(v.data(), v.data() + v.size(), x);
    if (ec != std::errc() || ptr != v.data() + v.size() || !std::isfinite(x))
      throw UsageError(name + ": not a number: '" + v + "'");
    return x;
  }
  long integer(const std::string& name, long fallback) {
    const std::string v = value(name);
    if (v.empty()) return fallback;
    long x = 0;
    auto [ptr, ec] = std::from_chars(v.data(), v.data() + v.size(), x);
    if (ec != std::errc() || ptr != v.data() + v.size()) throw UsageError(name + ": not an integer: '" + v + "'");
    return x;
  }
  std::vector<std::string> positionals() const {
    for (const auto& s : a_)
      if (s.size() > 1 && s[0] == '-' && s[1] == '-') throw UsageError("unknown option " + s);
    return a_;
  }

 private:
  std::vector<std::string> a_;
};

}  // namespace vd::app
