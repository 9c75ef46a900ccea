#include "tools/output/progress.h"

#include "core/format.h"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <ostream>

namespace jetshell {

Progress::Progress(std::ostream& out, bool interactive)
    : out_(out), interactive_(interactive), start_(std::chrono::steady_clock::now()), lastDraw_(start_) {}

bool Progress::isTerminal(int fd) { return ::isatty(fd) == 1; }

std::string Progress::formatDuration(double s) {
  char buffer[64];
  if (!std::isfinite(s) || s < 0) return "?";
  // An estimate from a tiny fraction done can exceed any int: hours are counted in a double, and a million or
  // more are shown in scientific notation.
  if (s >= 3.6e9) return formatNumber("%.2e h", s / 3600);
  if (s < 10) std::snprintf(buffer, sizeof buffer, "%.1f s", s);
  else if (s < 60) std::snprintf(buffer, sizeof buffer, "%.0f s", s);
  else if (s < 3600) std::snprintf(buffer, sizeof buffer, "%d min %02d s", static_cast<int>(s) / 60, static_cast<int>(s) % 60);
  else
    std::snprintf(buffer, sizeof buffer, "%.0f h %02d min", std::floor(s / 3600),
                  static_cast<int>(std::fmod(s, 3600) / 60));
  return buffer;
}

void Progress::clearBar() {
  if (barShown_) out_ << "\r\033[2K";
  barShown_ = false;
}

void Progress::log(const std::string& line) {
  clearBar();
  out_ << line << '\n';
  if (interactive_ && !bar_.empty()) {
    out_ << bar_ << std::flush;
    barShown_ = true;
  }
  out_.flush();
}

void Progress::update(double fraction, const std::string& status) {
  if (!interactive_) return;
  const auto now = std::chrono::steady_clock::now();
  // Redrawing more than ~20 times a second only costs terminal time.
  if (barShown_ && fraction < 1.0 && now - lastDraw_ < std::chrono::milliseconds(50)) return;
  lastDraw_ = now;
  fraction = std::clamp(fraction, 0.0, 1.0);
  const double elapsed = std::chrono::duration<double>(now - start_).count();
  const int width = 30, filled = static_cast<int>(std::lround(fraction * width));
  std::string bar = "[" + std::string(static_cast<std::size_t>(filled), '#') +
                    std::string(static_cast<std::size_t>(width - filled), '.') + "] ";
  char percent[16];
  std::snprintf(percent, sizeof percent, "%3.0f%% ", 100 * fraction);
  bar += percent + status;
  bar += fraction > 0 ? "  ETA " + formatDuration(elapsed * (1 - fraction) / fraction) : "  ETA ?";
  bar_ = bar;
  clearBar();
  out_ << bar_ << std::flush;
  barShown_ = true;
}

void Progress::finish() {
  clearBar();
  bar_.clear();
  out_.flush();
}

}  // namespace jetshell
