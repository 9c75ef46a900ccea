// The rows of probes.csv, and the few of them a run keeps in memory.
//
// Data flow: RunOutput::record() makes one ProbeRow per step and appends it to probes.csv at once (the file holds
// every row); it keeps the last row (summary.json, a row recorded again) and, for probes.png and
// contact_forces.png, PlotRows: the recorded rows in buckets of `stride` consecutive rows, at most kMaxPlotRows
// buckets (fewer for rows so wide that they would hold over kMaxPlotValues numbers), each kept as its first row and
// the least and the greatest value of each column over its rows. When one more bucket would not fit, neighbouring
// buckets are merged in pairs and the stride doubles, so the buckets stay evenly spaced over the whole run and no
// peak falls between them, however short.
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

/// The least and the greatest of each value of u and force over a bucket's rows.
struct RowRange {
  std::vector<double> uLow, uHigh, forceLow, forceHigh;

  explicit RowRange(const ProbeRow& row = {}) : uLow(row.u), uHigh(row.u), forceLow(row.force), forceHigh(row.force) {}
  /// Widens the range to hold `row` (a row of the same widths; another is left out).
  void include(const ProbeRow& row) {
    if (row.u.size() != uLow.size() || row.force.size() != forceLow.size()) return;
    widen(uLow, uHigh, row.u);
    widen(forceLow, forceHigh, row.force);
  }
  void include(const RowRange& r) {
    if (r.uLow.size() != uLow.size() || r.forceLow.size() != forceLow.size()) return;
    widen(uLow, uHigh, r.uLow);
    widen(uLow, uHigh, r.uHigh);
    widen(forceLow, forceHigh, r.forceLow);
    widen(forceLow, forceHigh, r.forceHigh);
  }
  /// Whether `row` has the range's widths and lies within it.
  bool holds(const ProbeRow& row) const {
    return within(uLow, uHigh, row.u) && within(forceLow, forceHigh, row.force);
  }

 private:
  static void widen(std::vector<double>& low, std::vector<double>& high, const std::vector<double>& v) {
    for (std::size_t i = 0; i < v.size(); ++i) {
      low[i] = std::min(low[i], v[i]);
      high[i] = std::max(high[i], v[i]);
    }
  }
  static bool within(const std::vector<double>& low, const std::vector<double>& high, const std::vector<double>& v) {
    if (low.size() != v.size() || high.size() != v.size()) return false;
    for (std::size_t i = 0; i < v.size(); ++i)
      if (!(low[i] <= v[i] && v[i] <= high[i])) return false;
    return true;
  }
};

/// A plot's curve of this many points is as smooth as the picture can show (plots are 1,000-2,000 pixels wide).
constexpr std::size_t kMaxPlotRows = 2048;
/// The numbers the kept rows and their ranges may hold together (128 MB): a scene's probes and volume actors make
/// rows of up to 330,003 numbers (InputLimits::maxConditions probes, maxActors volume actors).
constexpr std::size_t kMaxPlotValues = std::size_t{1} << 24;

/// The recorded rows in buckets of `stride`: bucket k holds the recorded rows k stride, ..., (k + 1) stride - 1
/// (counted in recorded rows, not steps). rows[k] is its first row; ranges[k] spans the values of its rows
/// recorded before the last recorded row (that one is folded in when the next is added: a step recorded again
/// replaces it, and a range cannot forget a value), and the first row always.
struct PlotRows {
  std::vector<ProbeRow> rows;
  std::vector<RowRange> ranges;
  std::int64_t stride = 1;    // a power of two
  std::int64_t recorded = 0;  // rows recorded in all
  std::size_t capacity = kMaxPlotRows;  // even (capacityFor)

  /// How many buckets of rows of `valuesPerRow` numbers (step, time, load factor, u, force) are kept:
  /// kMaxPlotRows, or fewer to hold at most kMaxPlotValues numbers with their ranges, at least 2; even, so that
  /// add() keeps the row it adds.
  static std::size_t capacityFor(std::size_t valuesPerRow) {
    const std::size_t pairs = kMaxPlotValues / (6 * (valuesPerRow > 0 ? valuesPerRow : 1));
    return 2 * std::clamp<std::size_t>(pairs, 1, kMaxPlotRows / 2);
  }

  /// The row of a step not recorded before. `previous` is the row recorded before it (RunOutput's last row; none
  /// for the first row): its values join its bucket's range now.
  void add(const ProbeRow& row, const ProbeRow* previous) {
    if (previous && !ranges.empty()) ranges.back().include(*previous);
    if (recorded++ % stride != 0) return;
    rows.push_back(row);
    ranges.emplace_back(row);
    if (rows.size() <= capacity) return;
    // Merge the buckets in pairs: keep the first row of each even-indexed bucket, with both ranges. The capacity
    // is even, so the row just added starts a bucket of its own. From k = 1: a vector moved onto itself is left
    // empty.
    ranges[0].include(ranges[1]);
    for (std::size_t k = 1; 2 * k < rows.size(); ++k) {
      rows[k] = std::move(rows[2 * k]);
      ranges[k] = std::move(ranges[2 * k]);
      if (2 * k + 1 < ranges.size()) ranges[k].include(ranges[2 * k + 1]);
    }
    rows.resize((rows.size() + 1) / 2);
    ranges.resize(rows.size());
    stride *= 2;
  }
  /// The last recorded row again (its step recorded a second time): kept when it starts a bucket (its range then
  /// holds it alone); otherwise not yet in its bucket's range.
  void replaceLast(const ProbeRow& row) {
    if (recorded > 0 && (recorded - 1) % stride == 0 && !rows.empty()) {
      rows.back() = row;
      ranges.back() = RowRange(row);
    }
  }
  /// The buckets with the last recorded row folded into the last one's range: what the plots draw.
  PlotRows closedWith(const ProbeRow* last) const {
    PlotRows closed = *this;
    if (last && !closed.ranges.empty()) closed.ranges.back().include(*last);
    return closed;
  }
  /// Whether the counts agree with each other as add() leaves them (a checkpoint's are checked against this), and
  /// each bucket's range holds its first row.
  bool consistent() const {
    const bool powerOfTwo = stride >= 1 && (stride & (stride - 1)) == 0;
    if (!powerOfTwo || recorded < 0 || capacity % 2 != 0 || rows.size() > capacity || ranges.size() != rows.size() ||
        static_cast<std::int64_t>(rows.size()) != (recorded + stride - 1) / stride)
      return false;
    for (std::size_t k = 0; k < rows.size(); ++k)
      if (!ranges[k].holds(rows[k])) return false;
    return true;
  }
};

}  // namespace jetshell
