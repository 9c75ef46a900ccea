// printf-style formatting of one number into a std::string, for reports, logs and summaries.
#pragma once

#include <cstdio>
#include <string>

namespace jetshell {

/// fmt holds exactly one conversion of a double (for example "%.3f"); the text is cut at 63 characters.
inline std::string formatNumber(const char* fmt, double v) {
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, fmt, v);
  return buffer;
}

}  // namespace jetshell
