// Numbers as text: the one place a printf format meets a double, so that the
// report, the comparison table, the SVG and the messages format alike.
#pragma once

#include <string>

namespace vd {

// x by a printf format for one double ("%.6g": six significant digits, the
// tables'; "%.17g": every digit, the JSON's).
std::string number_text(double x, const char* format = "%.6g");

}  // namespace vd
