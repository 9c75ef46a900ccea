#include "tools/scene/run_plots.h"

#include <algorithm>
#include <cmath>

namespace jetshell {
namespace {

/// One curve per component of each named vector series: `values[3 k + c]` is component c of `names[k]` at each
/// abscissa.
std::vector<PlotSeries> componentCurves(const std::vector<std::string>& names, const std::string& symbol,
                                        const std::vector<double>& abscissa,
                                        const std::vector<std::vector<double>>& values) {
  static const char* colors[3] = {"#d62728", "#2ca02c", "#1f77b4"};
  double largest = 0.0;
  for (const std::vector<double>& series : values)
    for (double v : series) largest = std::max(largest, std::abs(v));
  std::vector<PlotSeries> curves;
  for (std::size_t k = 0; k < names.size() && 3 * k + 2 < values.size(); ++k)
    for (std::size_t c = 0; c < 3; ++c) {
      const std::vector<double>& series = values[3 * k + c];
      double peak = 0.0;
      for (double v : series) peak = std::max(peak, std::abs(v));
      if (peak <= 1e-3 * largest) continue;  // components that stay at zero only clutter the plot
      curves.emplace_back(names[k] + " " + symbol + std::string(1, static_cast<char>('x' + c)), abscissa, series,
                          "lines", colors[c], 1 + static_cast<int>(k % 5));
    }
  return curves;
}

}  // namespace

std::vector<PlotSeries> rowCurves(const std::vector<std::string>& names, const std::string& symbol,
                                  const PlotRows& rows, const std::optional<ProbeRow>& last, RowField field) {
  const bool u = field == RowField::u;
  std::vector<double> abscissa;
  std::vector<std::vector<double>> values(3 * names.size());
  const auto point = [&](double time, const std::vector<double>& v) {
    abscissa.push_back(time);
    for (std::size_t i = 0; i < values.size(); ++i) values[i].push_back(v[i]);
  };
  for (std::size_t k = 0; k < rows.rows.size() && k < rows.ranges.size(); ++k) {
    const std::vector<double>& first = u ? rows.rows[k].u : rows.rows[k].force;
    const std::vector<double>& low = u ? rows.ranges[k].uLow : rows.ranges[k].forceLow;
    const std::vector<double>& high = u ? rows.ranges[k].uHigh : rows.ranges[k].forceHigh;
    if (first.size() != values.size() || low.size() != values.size() || high.size() != values.size()) continue;
    point(rows.rows[k].time, first);
    if (low != first || high != first) {  // a bucket of rows that differ: its span, drawn upright
      point(rows.rows[k].time, low);
      point(rows.rows[k].time, high);
    }
  }
  if (last && (rows.rows.empty() || last->step != rows.rows.back().step)) {
    const std::vector<double>& v = u ? last->u : last->force;
    if (v.size() == values.size()) point(last->time, v);
  }
  return componentCurves(names, symbol, abscissa, values);
}

}  // namespace jetshell
