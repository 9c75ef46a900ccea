#include "tools/render/plot.h"

#include "core/mesh.h"
#include "tools/output/vtu.h"

#include <fcntl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace jetshell {
namespace {

/// A gnuplot double-quoted string literal.
std::string quoted(const std::string& s) {
  std::string out = "\"";
  for (char c : s) {
    if (c == '"' || c == '\\') out += '\\';
    out += c;
  }
  return out + "\"";
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
  s << "set terminal pngcairo noenhanced size " << spec.width << "," << spec.height << " font \"Sans,11\"\n"
    << "set output " << quoted(pngPath) << "\n"
    << "set title " << quoted(spec.title) << "\n"
    << "set xlabel " << quoted(spec.xLabel) << "\n"
    << "set ylabel " << quoted(spec.yLabel) << "\n"
    << "set grid\nset key outside right top\n";
  if (spec.logX) s << "set logscale x\n";
  if (spec.logY) s << "set logscale y\n";
  s << "plot ";
  for (std::size_t k = 0; k < spec.series.size(); ++k) {
    const std::string& style = spec.series[k].style;
    s << (k ? ", \\\n     " : "") << quoted(dataFiles[k]) << " using 1:2 with "
      << (style == "points" ? "points pt 7 ps 0.8" : style == "linespoints" ? "linespoints pt 7 ps 0.6 lw 2" : "lines lw 2")
      << " dt " << spec.series[k].dashType
      << (spec.series[k].color.empty() ? "" : " lc rgb " + quoted(spec.series[k].color))
      << " title " << quoted(spec.series[k].label);
  }
  s << "\n";
  return s.str();
}

void plotPng(const PlotSpec& spec, const std::string& pngPath) {
  if (spec.series.empty()) throw InputError(pngPath + ": nothing to plot (no series)");
  for (const PlotSeries& p : spec.series)
    if (p.x.size() != p.y.size())
      throw InputError(pngPath + ": series '" + p.label + "' has " + std::to_string(p.x.size()) + " x values and " +
                       std::to_string(p.y.size()) + " y values");
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
  // gnuplot writes the PNG next to the target, then it is renamed (atomic like every other output).
  const std::string temporary = pngPath + ".tmp" + std::to_string(::getpid()) + ".png";
  const std::string script = (work / "plot.gp").string(), errors = (work / "errors.txt").string();
  std::ofstream(script) << gnuplotScript(spec, files, temporary);
  const int status = runGnuplot(script, errors);
  std::string firstError;
  std::getline(std::ifstream(errors) >> std::ws, firstError);
  std::error_code ec;
  fs::remove_all(work, ec);
  if (status != 0 || !fs::exists(temporary)) {
    fs::remove(temporary, ec);
    throw InputError(pngPath + ": gnuplot failed" + (firstError.empty() ? "" : ": " + firstError));
  }
  fs::rename(temporary, pngPath, ec);
  if (ec) throw InputError(pngPath + ": cannot write (" + ec.message() + ")");
}

}  // namespace jetshell
