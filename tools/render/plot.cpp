#include "tools/render/plot.h"

#include "core/mesh.h"
#include "tools/output/atomic_file.h"
#include "tools/output/vtu.h"

#include <fcntl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace jetshell {
namespace {

/// Longest text (title, label, series name) passed to gnuplot; longer text is cut.
constexpr std::size_t kMaxPlotText = 200;

/// A gnuplot single-quoted string literal holding text that may come from a user (scene description, probe names,
/// paths). gnuplot substitutes backquoted commands and interprets escapes only in double-quoted strings; inside
/// single quotes the one special character is the quote itself, and gnuplot 5.4 misreads a doubled quote at the
/// start of a string, so a quote becomes the typographic one (U+2019). A newline would end the command and start
/// a new one, so control characters become spaces; backquotes are dropped as a second line of defence.
std::string literal(const std::string& text) {
  std::string out = "'";
  std::size_t kept = 0;
  for (const char c : text) {
    if (kept == kMaxPlotText) break;
    const auto u = static_cast<unsigned char>(c);
    if (c == '`') continue;
    ++kept;
    if (u < 0x20 || u == 0x7f) {
      out += ' ';
    } else if (c == '\'') {
      out += "\u2019";
    } else {
      out += c;
    }
  }
  return out + "'";
}

/// A colour gnuplot may see: "#rrggbb" only (anything else is refused, not passed on).
bool isHexColour(const std::string& c) {
  if (c.size() != 7 || c[0] != '#') return false;
  for (std::size_t i = 1; i < 7; ++i)
    if (!std::isxdigit(static_cast<unsigned char>(c[i]))) return false;
  return true;
}

/// Runs `gnuplot script`; returns its exit status and fills `errors` with what it printed on stderr.
int runGnuplot(const std::string& script, const std::string& errorFile) {
  const pid_t pid = ::fork();
  if (pid < 0) return -1;
  if (pid == 0) {
    const int fd = ::open(errorFile.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0600);
    if (fd >= 0) {
      ::dup2(fd, STDERR_FILENO);
      ::dup2(fd, STDOUT_FILENO);
      ::close(fd);
    }
    const char* argv[] = {"gnuplot", script.c_str(), nullptr};
    ::execvp("gnuplot", const_cast<char* const*>(argv));
    ::_exit(127);
  }
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0) {
    if (errno != EINTR) return -1;  // ECHILD and the like: no status will ever come
  }
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

}  // namespace

bool gnuplotAvailable() {
  const char* path = std::getenv("PATH");
  if (!path) return false;
  std::stringstream dirs(path);
  for (std::string dir; std::getline(dirs, dir, ':');)
    if (!dir.empty() && ::access((dir + "/gnuplot").c_str(), X_OK) == 0) return true;
  return false;
}

std::string gnuplotScript(const PlotSpec& spec, const std::vector<std::string>& dataFiles, const std::string& pngPath) {
  std::ostringstream s;
  s << "set terminal pngcairo noenhanced size " << spec.width << "," << spec.height << " font 'Sans,11'\n"
    << "set output " << literal(pngPath) << "\n"
    << "set title " << literal(spec.title) << "\n"
    << "set xlabel " << literal(spec.xLabel) << "\n"
    << "set ylabel " << literal(spec.yLabel) << "\n"
    << "set grid\nset key outside right top\n";
  if (spec.logX) s << "set logscale x\n";
  if (spec.logY) s << "set logscale y\n";
  s << "plot ";
  for (std::size_t k = 0; k < spec.series.size(); ++k) {
    const std::string& style = spec.series[k].style;
    s << (k ? ", \\\n     " : "") << literal(dataFiles[k]) << " using 1:2 with "
      << (style == "points" ? "points pt 7 ps 0.8" : style == "linespoints" ? "linespoints pt 7 ps 0.6 lw 2" : "lines lw 2")
      << " dt " << spec.series[k].dashType
      << (spec.series[k].color.empty() ? "" : " lc rgb " + literal(spec.series[k].color))
      << " title " << literal(spec.series[k].label);
  }
  s << "\n";
  return s.str();
}

void plotPng(const PlotSpec& spec, const std::string& pngPath) {
  if (spec.series.empty()) throw InputError(pngPath + ": nothing to plot (no series)");
  if (spec.width < 16 || spec.width > 8192 || spec.height < 16 || spec.height > 8192)
    throw InputError(pngPath + ": plot size " + std::to_string(spec.width) + "x" + std::to_string(spec.height) +
                     " is outside 16..8192 pixels");
  for (const PlotSeries& p : spec.series) {
    if (p.x.size() != p.y.size())
      throw InputError(pngPath + ": series '" + p.label + "' has " + std::to_string(p.x.size()) + " x values and " +
                       std::to_string(p.y.size()) + " y values");
    if (!p.color.empty() && !isHexColour(p.color))
      throw InputError(pngPath + ": series '" + p.label + "' has colour '" + p.color + "' (expected #rrggbb)");
  }
  if (!gnuplotAvailable()) throw InputError(pngPath + ": gnuplot is not installed (apt-get install gnuplot-nox)");
  namespace fs = std::filesystem;
  char pattern[] = "/tmp/jetshell-plot-XXXXXX";
  if (!::mkdtemp(pattern)) throw InputError(pngPath + ": cannot create a temporary directory");
  const fs::path work = pattern;
  std::vector<std::string> files;
  for (std::size_t k = 0; k < spec.series.size(); ++k) {
    const std::string file = (work / ("series" + std::to_string(k) + ".dat")).string();
    std::ofstream out(file);
    const PlotSeries& p = spec.series[k];
    for (std::size_t i = 0; i < p.x.size(); ++i) {
      // Non-finite values break a curve instead of breaking gnuplot.
      if (std::isfinite(p.x[i]) && std::isfinite(p.y[i])) out << formatDouble(p.x[i]) << ' ' << formatDouble(p.y[i]) << '\n';
      else out << '\n';
    }
    files.push_back(file);
  }
  // gnuplot only ever sees names of our own making: it draws into the private directory, and the picture is
  // then copied to the target atomically (like every other output), so the user's path never reaches it.
  const std::string drawn = (work / "plot.png").string();
  const std::string script = (work / "plot.gp").string(), errors = (work / "errors.txt").string();
  std::ofstream(script) << gnuplotScript(spec, files, drawn);
  const int status = runGnuplot(script, errors);
  std::string firstError;
  std::getline(std::ifstream(errors) >> std::ws, firstError);
  std::string picture;
  if (status == 0) {
    std::ifstream in(drawn, std::ios::binary);
    std::ostringstream bytes;
    bytes << in.rdbuf();
    picture = bytes.str();
  }
  std::error_code ec;
  fs::remove_all(work, ec);
  if (status != 0 || picture.empty())
    throw InputError(pngPath + ": gnuplot failed" + (firstError.empty() ? "" : ": " + firstError));
  writeFileAtomically(pngPath, picture);
}

}  // namespace jetshell
