// Progress of a run: on a terminal a bar with the fraction done and the ETA, redrawn in place below the log
// lines; otherwise (a pipe, a file, CI) only the log lines, one per step.
#pragma once

#include <chrono>
#include <iosfwd>
#include <string>

namespace jetshell {

class Progress {
 public:
  /// `interactive`: draw the bar (pass isTerminal(stderr) normally). Output goes to `out`.
  Progress(std::ostream& out, bool interactive);
  /// Prints one log line (above the bar when it is shown).
  void log(const std::string& line);
  /// Updates the bar: `fraction` in [0, 1] of the run done; `status` is a short text shown beside it.
  void update(double fraction, const std::string& status);
  /// Removes the bar (call before the final report).
  void finish();

  /// True when the stream behind file descriptor fd is a terminal.
  static bool isTerminal(int fd);
  /// "1 h 02 min", "3 min 05 s", "12 s", "0.4 s".
  static std::string formatDuration(double seconds);

 private:
  void clearBar();
  std::ostream& out_;
  bool interactive_;
  bool barShown_ = false;
  std::string bar_;
  std::chrono::steady_clock::time_point start_;
  std::chrono::steady_clock::time_point lastDraw_;
};

}  // namespace jetshell
