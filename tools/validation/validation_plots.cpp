#include "tools/validation/validation_plots.h"

#include "tools/render/plot.h"

#include <algorithm>
#include <map>

namespace jetshell::validation {

void plotLoadPath(const Benchmark& b, const BenchmarkResult& r, const std::string& pngPath) {
  static const char* colors[] = {"#1f77b4", "#d62728", "#2ca02c", "#9467bd"};
  PlotSpec spec;
  spec.title = b.name + ": " + std::to_string(r.vertices) + " vertices, " + toString(r.clamp) + " clamp, " +
               toString(r.solver);
  spec.xLabel = "displacement";
  spec.yLabel = "load factor lambda";
  for (std::size_t q = 0; q < r.quantities.size(); ++q) {
    const char* color = colors[q % 4];
    const bool table = b.reference.source.find(".tsv") != std::string::npos;
    PlotSeries reference{r.quantities[q] + " reference (" + (table ? "Sze et al. 2004" : b.reference.source) + ")",
                         {}, {}, "points", color, 1};
    for (int row = 0; row < b.reference.rows(); ++row) {
      reference.x.push_back(b.reference.value[row][q]);
      reference.y.push_back(b.reference.lambda[row]);
    }
    PlotSeries computed{r.quantities[q] + " jetshell", {0.0}, {0.0}, "linespoints", color, 1};
    for (const BenchmarkRow& row : r.rows) {
      computed.x.push_back(row.computed[q]);
      computed.y.push_back(row.lambda);
    }
    spec.series.push_back(std::move(reference));
    spec.series.push_back(std::move(computed));
  }
  plotPng(spec, pngPath);
}

void plotErrorVersusTime(const std::vector<ErrorTimePoint>& points, const std::string& timeLabel,
                         const std::string& pngPath) {
  PlotSpec spec;
  spec.title = "Validation: max relative error over the load path against the time to compute it";
  spec.xLabel = timeLabel;
  spec.yLabel = "max relative error";
  spec.logX = spec.logY = true;
  static const char* palette[] = {"#1f77b4", "#d62728", "#2ca02c", "#ff7f0e", "#9467bd", "#8c564b", "#e377c2",
                                  "#17becf"};
  std::map<std::string, std::string> colorOf;
  std::vector<std::string> order;
  std::map<std::string, PlotSeries> series;
  double tMin = 1e300, tMax = 0.0;
  for (const ErrorTimePoint& p : points) {
    if (!(p.seconds > 0.0) || !(p.error > 0.0)) continue;
    if (!series.count(p.series)) {
      order.push_back(p.series);
      if (!colorOf.count(p.colorKey)) colorOf[p.colorKey] = palette[colorOf.size() % 8];
      series[p.series] = PlotSeries{p.series, {}, {}, "linespoints", colorOf[p.colorKey], p.dashType};
    }
    series[p.series].x.push_back(p.seconds);
    series[p.series].y.push_back(p.error);
    tMin = std::min(tMin, p.seconds);
    tMax = std::max(tMax, p.seconds);
  }
  for (const std::string& name : order) spec.series.push_back(series[name]);
  if (tMax > 0.0) spec.series.push_back(PlotSeries{"1% target", {tMin, tMax}, {0.01, 0.01}, "lines", "#000000", 2});
  plotPng(spec, pngPath);
}

}  // namespace jetshell::validation
