// PNG plots of curves (probe histories, validation curves, fits), drawn in-process with cairo. Titles, axis
// labels and series names, which may come from a scene, are only ever drawn as glyphs: no text is handed to
// another program or interpreter.
#pragma once

#include <cstddef>
#include <cstdint>
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
  std::vector<double> x, y;         // a non-finite value (or one ≤ 0 on a log axis) breaks the curve
  std::string style = "lines";      // lines | points | linespoints
  std::string color;                // "#rrggbb", or "" for the next colour of the default sequence
  int dashType = 1;                 // 1 solid, 2 dashed, 3 dotted, 4 dash-dot, 5 dash-dot-dot (cycles beyond)
};

struct PlotSpec {
  std::string title, xLabel, yLabel;
  std::vector<PlotSeries> series;
  bool logX = false, logY = false;
  int width = 1000, height = 700;
};

/// Bounds on what a plot accepts; text beyond kMaxPlotText code points is cut.
constexpr int kMinPlotSize = 16, kMaxPlotSize = 4096;
constexpr std::size_t kMaxPlotSeries = 1000;
constexpr std::size_t kMaxPlotPoints = 50'000'000;  // over all series
constexpr std::size_t kMaxPlotText = 200;

/// Draws the plot into 8-bit sRGB bytes (row-major RGB, width × height × 3). Axes are scaled to the data; series
/// beyond what the legend can show are drawn but not listed. Throws InputError, naming `where`, when a series has
/// mismatched x and y, an unknown style or a colour that is not #rrggbb, or when a bound above is exceeded.
std::vector<std::uint8_t> drawPlot(const PlotSpec& spec, const std::string& where);

/// drawPlot, written atomically as a PNG.
void plotPng(const PlotSpec& spec, const std::string& pngPath);

/// Text as a plot draws it: valid UTF-8 (each invalid byte becomes U+FFFD), control characters as spaces, at
/// most kMaxPlotText code points.
std::string drawableText(const std::string& text);

}  // namespace jetshell
