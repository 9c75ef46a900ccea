#include "tools/output/plot_rows.h"

#include <catch2/catch.hpp>

#include <algorithm>
#include <optional>

using namespace jetshell;

namespace {

/// Records `row` as RunOutput::record() does: the row recorded before it joins its bucket's range.
void recordRow(PlotRows& plot, std::optional<ProbeRow>& last, const ProbeRow& row) {
  plot.add(row, last ? &*last : nullptr);
  last = row;
}

}  // namespace

TEST_CASE("plot rows: every stride-th row, at most kMaxPlotRows, evenly spaced however many are recorded") {
  PlotRows plot;
  std::optional<ProbeRow> last;
  for (int step = 0; step < 10000; ++step) {
    recordRow(plot, last, {step, 0.5 * step, 1.0, {double(step)}, {}});
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
  plot.add({10000, 5000.0, 1.0, {10000.0}, {}}, &*last);
  plot.replaceLast({10000, 5000.0, 1.0, {-1.0}, {}});
  CHECK(plot.rows.back().step == 10000);
  CHECK(plot.rows.back().u[0] == -1.0);
  CHECK(plot.ranges.back().uLow == std::vector<double>{-1.0});
  CHECK(plot.ranges.back().uHigh == std::vector<double>{-1.0});
  CHECK(plot.consistent());
  // A changed count is not, nor a range that does not hold its first row.
  PlotRows edited = plot;
  edited.recorded += 8;
  CHECK_FALSE(edited.consistent());
  edited = plot;
  edited.stride = 6;
  CHECK_FALSE(edited.consistent());
  edited = plot;
  edited.ranges[3].uHigh[0] = edited.rows[3].u[0] - 1.0;
  CHECK_FALSE(edited.consistent());
  edited = plot;
  edited.ranges.pop_back();
  CHECK_FALSE(edited.consistent());
}

TEST_CASE("plot rows: each bucket spans the least and greatest of its rows, so a one-step peak is kept") {
  // A signal at rest with two one-row spikes, in u and in force, that no stride-th row lands on.
  const int n = 9001;
  const auto value = [](int step) { return step == 5003 ? 7.0 : step == 7001 ? -3.0 : 0.001 * (step % 5); };
  PlotRows plot;
  std::optional<ProbeRow> last;
  for (int step = 0; step < n; ++step) {
    recordRow(plot, last, {step, 0.01 * step, 1.0, {value(step), 0.0, 0.0}, {-value(step), 0.0, 0.0}});
    REQUIRE(plot.consistent());
  }
  REQUIRE(plot.stride == 8);
  // Every row but the last is in its bucket's range; closing adds the last.
  const PlotRows closed = plot.closedWith(&*last);
  REQUIRE(closed.rows.size() == static_cast<std::size_t>((n + 7) / 8));
  for (std::size_t k = 0; k < closed.rows.size(); ++k) {
    double low = value(8 * static_cast<int>(k)), high = low;
    for (int step = 8 * static_cast<int>(k); step < std::min(n, 8 * static_cast<int>(k) + 8); ++step) {
      low = std::min(low, value(step));
      high = std::max(high, value(step));
    }
    INFO("bucket " << k);
    CHECK(closed.ranges[k].uLow[0] == low);
    CHECK(closed.ranges[k].uHigh[0] == high);
    CHECK(closed.ranges[k].forceLow[0] == -high);
    CHECK(closed.ranges[k].forceHigh[0] == -low);
  }
  CHECK(closed.ranges[5003 / 8].uHigh[0] == 7.0);
  CHECK(closed.ranges[7001 / 8].uLow[0] == -3.0);
  // The last row (9,000) starts a bucket; row 9,001 does not. Recorded again with another value, the value it
  // replaced is in no range.
  recordRow(plot, last, {n, 0.01 * n, 1.0, {50.0, 0.0, 0.0}, {0.0, 0.0, 0.0}});
  plot.replaceLast({n, 0.01 * n, 1.0, {0.5, 0.0, 0.0}, {0.0, 0.0, 0.0}});
  last = ProbeRow{n, 0.01 * n, 1.0, {0.5, 0.0, 0.0}, {0.0, 0.0, 0.0}};
  CHECK(plot.closedWith(&*last).ranges.back().uHigh[0] == 0.5);
  // The next row folds the replacement in.
  recordRow(plot, last, {n + 1, 0.01 * (n + 1), 1.0, {0.0, 0.0, 0.0}, {0.0, 0.0, 0.0}});
  CHECK(plot.ranges.back().uHigh[0] == 0.5);
}

TEST_CASE("plot rows: wide rows are kept fewer, so that they hold at most kMaxPlotValues numbers") {
  CHECK(PlotRows::capacityFor(3) == kMaxPlotRows);
  CHECK(PlotRows::capacityFor(2730) == kMaxPlotRows);
  CHECK(PlotRows::capacityFor(2731) == 2046);
  CHECK(PlotRows::capacityFor(330'003) == 16);
  CHECK(PlotRows::capacityFor(std::size_t{1} << 40) == 2);
  PlotRows plot;
  plot.capacity = 2;
  std::optional<ProbeRow> last;
  for (int step = 0; step < 9; ++step) recordRow(plot, last, {step, 0.0, 1.0, {double(step)}, {}});
  CHECK(plot.consistent());
  REQUIRE(plot.rows.size() == 2);
  CHECK(plot.rows[0].u[0] == 0.0);
  CHECK(plot.rows[1].u[0] == 8.0);
  CHECK(plot.ranges[0].uHigh[0] == 7.0);
}
