#include "mesh/number_text.h"

#include <cstdio>

namespace vd {

std::string number_text(double x, const char* format) {
  char text[64];
  std::snprintf(text, sizeof text, format, x);
  return text;
}

}  // namespace vd
