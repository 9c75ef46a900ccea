// PNG plots of curves through gnuplot (Debian's gnuplot-nox, pngcairo terminal): used for probe histories,
// validation curves and fits.
#pragma once

#include <string>
#include <vector>

namespace jetshell {

struct PlotSeries {
  std::string label;
  std::vector<double> x, y;
  std::string style = "lines";  // lines | points | linespoints
};

struct PlotSpec {
  std::string title, xLabel, yLabel;
  std::vector<PlotSeries> series;
  bool logX = false, logY = false;
  int width = 1000, height = 700;
};

/// True when a gnuplot executable is on the PATH.
bool gnuplotAvailable();

/// Draws the series into a PNG (written atomically). Throws InputError when a series has mismatched x and y,
/// when gnuplot is missing, or when it fails (its first error line is quoted).
void plotPng(const PlotSpec& spec, const std::string& pngPath);

/// The gnuplot script plotPng runs (data files named by `dataFiles`, one per series), for inspection and tests.
std::string gnuplotScript(const PlotSpec& spec, const std::vector<std::string>& dataFiles, const std::string& pngPath);

}  // namespace jetshell
