// PNG charts of the validation: computed against reference load paths, and error against time for the
// convergence study. Drawn with tools/render/plot.h.
#pragma once

#include "validation/benchmark.h"

#include <string>
#include <vector>

namespace jetshell::validation {

/// Load factor λ (vertical) against every quantity (horizontal): the computed path as lines with points, the
/// reference as points. Throws InputError when it cannot be drawn or written.
void plotLoadPath(const Benchmark& benchmark, const BenchmarkResult& result, const std::string& pngPath);

/// One point of the error-versus-time chart.
struct ErrorTimePoint {
  std::string series;  // e.g. "slit-annular-plate, mirrored clamp"
  double seconds = 0.0;
  double error = 0.0;  // relative, > 0
  std::string colorKey;  // series with the same key share a colour (e.g. the benchmark)
  int dashType = 1;      // PlotSeries::dashType: 1 solid, 2 dashed, 3 dotted
};

/// Log–log chart of the max relative error over the path against the time to compute it, one line per series
/// (points in the given order, typically coarse to fine), with the 1% target as a dashed line.
void plotErrorVersusTime(const std::vector<ErrorTimePoint>& points, const std::string& timeLabel,
                         const std::string& pngPath);

}  // namespace jetshell::validation
