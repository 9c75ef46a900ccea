// PNG plots of curves through gnuplot (Debian's gnuplot-nox, pngcairo terminal): used for probe histories,
// validation curves and fits.
#pragma once

#include <string>
#include <utility>
#include <vector>

namespace jetshell {

struct PlotSeries {
  // A constructor (not aggregate initialisation) so callers may give any leading subset of the fields.
  PlotSeries(std::string label_ = "", std::vector<double> x_ = {}, std::vector<double> y_ = {},
             std::string style_ = "lines", std::string color_ = "", int dashType_ = 1)
      : label(std::move(label_)), x(std::move(x_)), y(std::move(y_)), style(std::move(style_)),
        color(std::move(color_)), dashType(dashType_) {}
  std::string label;
  std::vector<double> x, y;
  std::string style = "lines";  // lines | points | linespoints
  std::string color;            // "#rrggbb", or "" for gnuplot's sequence
  int dashType = 1;             // gnuplot dash type: 1 solid, 2 dashed, 3 dotted, ...
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
