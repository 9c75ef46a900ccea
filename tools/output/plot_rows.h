// The rows of probes.csv, and the few of them a run keeps in memory.
//
// Data flow: RunOutput::record() makes one ProbeRow per step and appends it to probes.csv at once (the file holds
// every row); it keeps the last row (summary.json, a row recorded again) and, for probes.png and
// contact_forces.png, PlotRows: every stride-th row, at most kMaxPlotRows of them (fewer for rows so wide that
// they would hold over kMaxPlotValues numbers). When one more would not fit, every other kept row is dropped and
// the stride doubles, so the kept rows stay evenly spaced over the whole run.
// A run's memory and its checkpoints hold these, not its history: both stay bounded however long it runs (they
// held every row twice, and a checkpoint every 10 steps made a 12,000-step run take 13 times as long).
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace jetshell {

/// One row of probes.csv.
struct ProbeRow {
  int step = 0;
  double time = 0.0, loadFactor = 0.0;
  std::vector<double> u;      // 3 per probe
  std::vector<double> force;  // 3 per volume actor whose contact force is recorded [N]
};

/// A plot's curve of this many points is as smooth as the picture can show (plots are 1,000-2,000 pixels wide).
constexpr std::size_t kMaxPlotRows = 2048;
/// The numbers the kept rows may hold together (128 MB): a scene's probes and volume actors make rows of up to
/// 330,003 numbers (InputLimits::maxConditions probes, maxActors volume actors).
constexpr std::size_t kMaxPlotValues = std::size_t{1} << 24;

/// The recorded rows 0, stride, 2 stride, ... (counted in recorded rows, not steps).
struct PlotRows {
  std::vector<ProbeRow> rows;
  std::int64_t stride = 1;    // a power of two
  std::int64_t recorded = 0;  // rows recorded in all
  std::size_t capacity = kMaxPlotRows;  // even (capacityFor)

  /// How many rows of `valuesPerRow` numbers (step, time, load factor, u, force) are kept: kMaxPlotRows, or
  /// fewer to hold at most kMaxPlotValues numbers, at least 2; even, so that add() keeps the row it adds.
  static std::size_t capacityFor(std::size_t valuesPerRow) {
    const std::size_t pairs = kMaxPlotValues / (2 * (valuesPerRow > 0 ? valuesPerRow : 1));
    return 2 * std::clamp<std::size_t>(pairs, 1, kMaxPlotRows / 2);
  }

  /// The row of a step not recorded before.
  void add(const ProbeRow& row) {
    if (recorded++ % stride != 0) return;
    rows.push_back(row);
    if (rows.size() <= capacity) return;
    // Keep the rows at even positions: those whose index is a multiple of the doubled stride. The capacity is
    // even, so the row just added stays. From k = 1: a vector moved onto itself is left empty.
    for (std::size_t k = 1; 2 * k < rows.size(); ++k) rows[k] = std::move(rows[2 * k]);
    rows.resize((rows.size() + 1) / 2);
    stride *= 2;
  }
  /// The last recorded row again (its step recorded a second time): kept when the last row was.
  void replaceLast(const ProbeRow& row) {
    if (recorded > 0 && (recorded - 1) % stride == 0 && !rows.empty()) rows.back() = row;
  }
  /// Whether the counts agree with each other as add() leaves them (a checkpoint's are checked against this).
  bool consistent() const {
    const bool powerOfTwo = stride >= 1 && (stride & (stride - 1)) == 0;
    return powerOfTwo && recorded >= 0 && capacity % 2 == 0 && rows.size() <= capacity &&
           static_cast<std::int64_t>(rows.size()) == (recorded + stride - 1) / stride;
  }
};

}  // namespace jetshell
