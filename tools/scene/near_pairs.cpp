#include "tools/scene/near_pairs.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <utility>
#include <vector>

namespace jetshell {

bool visitNearPairs(const Positions& points, double radius, const std::function<bool(int, int)>& visit,
                    long long visitsPerPoint) {
  const int n = static_cast<int>(points.rows());
  // Each point's cell, and the points sorted by cell: the points of a cell are one run.
  using Cell = std::array<std::int64_t, 3>;
  std::vector<std::pair<Cell, int>> sorted(static_cast<std::size_t>(n));
  for (int v = 0; v < n; ++v) {
    Cell c{};
    for (int k = 0; k < 3; ++k) {
      const double q = std::floor(points(v, k) / radius);
      if (!(std::abs(q) < 1e15)) return false;
      c[static_cast<std::size_t>(k)] = static_cast<std::int64_t>(q);
    }
    sorted[static_cast<std::size_t>(v)] = {c, v};
  }
  std::sort(sorted.begin(), sorted.end());
  // The filter of occupied cells: one bit per hashed cell, 8 bits a point.
  std::size_t bits = 64;
  while (bits < 8 * static_cast<std::size_t>(n)) bits *= 2;
  std::vector<std::uint64_t> occupied(bits / 64, 0);
  auto bit = [&](const Cell& c) {
    std::uint64_t x = static_cast<std::uint64_t>(c[0]) * 0x9E3779B97F4A7C15ull;
    x = (x ^ (x >> 29) ^ static_cast<std::uint64_t>(c[1])) * 0xBF58476D1CE4E5B9ull;
    x = (x ^ (x >> 31) ^ static_cast<std::uint64_t>(c[2])) * 0x94D049BB133111EBull;
    return (x ^ (x >> 32)) & (bits - 1);
  };
  for (const auto& entry : sorted) {
    const std::uint64_t b = bit(entry.first);
    occupied[b / 64] |= std::uint64_t{1} << (b % 64);
  }
  long long budget = visitsPerPoint * n;
  // Point v against the later points of one cell; false once the budget (points visited) is spent or visit says
  // stop.
  auto compare = [&](int v, const Cell& cell) {
    if (const std::uint64_t b = bit(cell); !(occupied[b / 64] >> (b % 64) & 1)) return true;
    for (auto it = std::lower_bound(sorted.begin(), sorted.end(), std::make_pair(cell, -1));
         it != sorted.end() && it->first == cell; ++it) {
      if (--budget < 0) return false;
      const int w = it->second;
      if (w <= v || (points.row(v) - points.row(w)).norm() >= radius) continue;
      if (!visit(v, w)) return false;
    }
    return true;
  };
  for (const auto& [cell, v] : sorted)
    for (int d = 0; d < 27; ++d)
      if (!compare(v, {cell[0] + d % 3 - 1, cell[1] + d / 3 % 3 - 1, cell[2] + d / 9 - 1})) return false;
  return true;
}

}  // namespace jetshell
