#include "tools/output/plot_rows.h"

#include <catch2/catch.hpp>

using namespace jetshell;

TEST_CASE("plot rows: every stride-th row, at most kMaxPlotRows, evenly spaced however many are recorded") {
  PlotRows plot;
  for (int step = 0; step < 10000; ++step) {
    plot.add({step, 0.5 * step, 1.0, {double(step)}, {}});
    REQUIRE(plot.consistent());
    REQUIRE(plot.rows.size() <= kMaxPlotRows);
  }
  // 10,000 rows need a stride of 8 (4 would keep 2,500).
  CHECK(plot.stride == 8);
  REQUIRE(plot.rows.size() == 1250);
  for (std::size_t k = 0; k < plot.rows.size(); ++k) {
    CHECK(plot.rows[k].step == 8 * static_cast<int>(k));
    CHECK(plot.rows[k].u == std::vector<double>{8.0 * static_cast<double>(k)});
  }
  // The last recorded row (9,999) was not kept: recording it again changes nothing kept.
  plot.replaceLast({9999, 0.0, 1.0, {-1.0}, {}});
  CHECK(plot.rows.back().step == 9992);
  CHECK(plot.rows.back().u[0] == 9992.0);
  // Row 10,000 is kept, and recording it again replaces it.
  plot.add({10000, 5000.0, 1.0, {10000.0}, {}});
  plot.replaceLast({10000, 5000.0, 1.0, {-1.0}, {}});
  CHECK(plot.rows.back().step == 10000);
  CHECK(plot.rows.back().u[0] == -1.0);
  CHECK(plot.consistent());
  // A changed count is not.
  PlotRows edited = plot;
  edited.recorded += 8;
  CHECK_FALSE(edited.consistent());
  edited = plot;
  edited.stride = 6;
  CHECK_FALSE(edited.consistent());
}

TEST_CASE("plot rows: wide rows are kept fewer, so that they hold at most kMaxPlotValues numbers") {
  CHECK(PlotRows::capacityFor(3) == kMaxPlotRows);
  CHECK(PlotRows::capacityFor(8192) == kMaxPlotRows);
  CHECK(PlotRows::capacityFor(8193) == 2046);
  CHECK(PlotRows::capacityFor(330'003) == 50);
  CHECK(PlotRows::capacityFor(std::size_t{1} << 40) == 2);
  PlotRows plot;
  plot.capacity = 2;
  for (int step = 0; step < 9; ++step) plot.add({step, 0.0, 1.0, {double(step)}, {}});
  CHECK(plot.consistent());
  REQUIRE(plot.rows.size() == 2);
  CHECK(plot.rows[0].u[0] == 0.0);
  CHECK(plot.rows[1].u[0] == 8.0);
}
