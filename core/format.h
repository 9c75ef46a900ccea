// printf-style formatting of one number into a std::string, for reports, logs and summaries.
#pragma once

#include <cstdio>
#include <string>

namespace jetshell {

/// fmt holds exactly one conversion of a double (for example "%.3f"). The whole text is returned: "%.3f" of
/// 1e300 is 305 characters, never a prefix that would read as another number.
inline std::string formatNumber(const char* fmt, double v) {
  const int n = std::snprintf(nullptr, 0, fmt, v);
  if (n < 0) return "?";
  std::string text(static_cast<std::size_t>(n), '\0');
  std::snprintf(text.data(), text.size() + 1, fmt, v);  // the terminator goes where std::string keeps its own
  return text;
}

}  // namespace jetshell
