#include "tools/scene/run_plots.h"

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <optional>

using namespace jetshell;

namespace {

/// A run's kept rows of one probe and one solid: u_x = value(step), F_y = -2 value(step), the rest zero.
template <class Value>
PlotRows keptRowsOf(int rows, const Value& value, std::optional<ProbeRow>& last) {
  PlotRows plot;
  for (int step = 0; step < rows; ++step) {
    const ProbeRow row{step, 0.01 * step, 1.0, {value(step), 0.0, 0.0}, {0.0, -2.0 * value(step), 0.0}};
    plot.add(row, last ? &*last : nullptr);
    last = row;
  }
  return plot;
}

const PlotSeries& plottedCurve(const std::vector<PlotSeries>& curves, const std::string& label) {
  const auto it = std::find_if(curves.begin(), curves.end(), [&](const PlotSeries& c) { return c.label == label; });
  REQUIRE(it != curves.end());
  return *it;
}

}  // namespace

TEST_CASE("run plots: a one-step peak between the kept rows is drawn, at its bucket's time") {
  const auto value = [](int step) { return step == 6001 ? 5.0 : 0.01 * std::sin(0.01 * step); };
  std::optional<ProbeRow> last;
  const PlotRows plot = keptRowsOf(9000, value, last);
  REQUIRE(plot.stride == 8);  // step 6,001 is no bucket's first row
  const PlotRows closed = plot.closedWith(&*last);
  const std::vector<PlotSeries> u = rowCurves({"B"}, "u", closed, last, RowField::u);
  REQUIRE(u.size() == 1);  // u_y and u_z stay at zero
  const PlotSeries& ux = plottedCurve(u, "B ux");
  REQUIRE(ux.x.size() == ux.y.size());
  const auto peak = std::max_element(ux.y.begin(), ux.y.end());
  CHECK(*peak == 5.0);
  CHECK(ux.x[static_cast<std::size_t>(peak - ux.y.begin())] == Approx(0.01 * 6000));
  CHECK(std::is_sorted(ux.x.begin(), ux.x.end()));
  CHECK(ux.x.back() == Approx(0.01 * 8999));  // the last row last
  CHECK(ux.y.back() == value(8999));
  // The same rows' forces: the solid's y component, the peak downwards.
  const std::vector<PlotSeries> forces = rowCurves({"floor"}, "F", closed, last, RowField::force);
  const PlotSeries& fy = plottedCurve(forces, "floor Fy");
  CHECK(*std::min_element(fy.y.begin(), fy.y.end()) == -10.0);
}

TEST_CASE("run plots: rows kept one by one are drawn one point each") {
  const auto value = [](int step) { return 0.5 * step; };
  std::optional<ProbeRow> last;
  const PlotRows plot = keptRowsOf(40, value, last);
  REQUIRE(plot.stride == 1);
  const std::vector<PlotSeries> curves = rowCurves({"B"}, "u", plot.closedWith(&*last), last, RowField::u);
  const PlotSeries& ux = plottedCurve(curves, "B ux");
  REQUIRE(ux.y.size() == 40);
  for (std::size_t k = 0; k < ux.y.size(); ++k) CHECK(ux.y[k] == value(static_cast<int>(k)));
}
