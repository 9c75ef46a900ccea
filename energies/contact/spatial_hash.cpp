#include "energies/contact/spatial_hash.h"

#include "core/mesh.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <omp.h>
#include <sstream>

namespace jetshell {
namespace {

using Cell = std::array<std::int64_t, 3>;

std::uint64_t cellHash(const Cell& cell) {
  std::uint64_t h = static_cast<std::uint64_t>(cell[0]) * 0x9E3779B97F4A7C15ull;
  h ^= static_cast<std::uint64_t>(cell[1]) * 0xC2B2AE3D27D4EB4Full + (h << 6) + (h >> 2);
  h ^= static_cast<std::uint64_t>(cell[2]) * 0x165667B19E3779F9ull + (h << 6) + (h >> 2);
  return h ^ (h >> 29);
}

/// A point in its bucket's run: its cell, coordinates and id.
struct Slot {
  Cell cell;
  std::array<double, 3> point;
  int id;
};

/// The 13 offsets to adjacent cells that come after (0, 0, 0) lexicographically: with the cell itself, every
/// unordered pair of adjacent cells once.
constexpr std::array<Cell, 13> kForward = {{{0, 0, 1},
                                           {0, 1, -1}, {0, 1, 0}, {0, 1, 1},
                                           {1, -1, -1}, {1, -1, 0}, {1, -1, 1},
                                           {1, 0, -1}, {1, 0, 0}, {1, 0, 1},
                                           {1, 1, -1}, {1, 1, 0}, {1, 1, 1}}};

/// A coordinate in cell units that a cell index can hold (finite, within 1e15 cells of the origin).
bool inCellRange(double v) { return std::isfinite(v) && std::abs(v) < 1e15; }

}  // namespace

bool hashablePoint(const double* point, double radius) {
  const double inv = 1.0 / radius;
  return inCellRange(point[0] * inv) && inCellRange(point[1] * inv) && inCellRange(point[2] * inv);
}

std::vector<PointPair> findClosePairs(const std::vector<double>& points, double radius, const PairFilter& filter) {
  if (!(std::isfinite(radius) && radius > 0.0)) throw InputError("broad phase: radius must be finite and > 0");
  const int n = static_cast<int>(points.size() / 3);
  std::vector<PointPair> pairs;
  if (n < 2) return pairs;
  std::size_t buckets = 1;
  while (buckets < 2 * static_cast<std::size_t>(n)) buckets <<= 1;
  const std::uint64_t mask = buckets - 1;
  const double inv = 1.0 / radius;
  std::vector<Cell> cellOf(static_cast<std::size_t>(n));
  std::vector<std::uint32_t> bucketOf(static_cast<std::size_t>(n));
  bool finite = true;
#pragma omp parallel for schedule(static) reduction(&& : finite) if (n >= 4096)
  for (int i = 0; i < n; ++i) {
    Cell& cell = cellOf[static_cast<std::size_t>(i)];
    for (int c = 0; c < 3; ++c) {
      const double v = points[3 * static_cast<std::size_t>(i) + c] * inv;
      const bool inRange = inCellRange(v);
      finite = finite && inRange;
      cell[static_cast<std::size_t>(c)] = inRange ? static_cast<std::int64_t>(std::floor(v)) : 0;
    }
    bucketOf[static_cast<std::size_t>(i)] = static_cast<std::uint32_t>(cellHash(cell) & mask);
  }
  if (!finite) {
    std::ostringstream m;
    m << "broad phase: a point coordinate is not finite, or lies more than 1e15 cells of " << radius
      << " m from the origin (a point-cloud radius too small for the scene's size)";
    throw InputError(m.str());
  }
  // Counting sort of the points by bucket; each slot keeps its point's id, cell and coordinates side by side.
  std::vector<std::uint32_t> start(buckets + 1, 0);
  for (int i = 0; i < n; ++i) ++start[bucketOf[static_cast<std::size_t>(i)] + 1];
  for (std::size_t b = 0; b < buckets; ++b) start[b + 1] += start[b];
  std::vector<Slot> slots(static_cast<std::size_t>(n));
  {
    std::vector<std::uint32_t> fill(start.begin(), start.end() - 1);
    for (int i = 0; i < n; ++i) {
      const std::size_t k = fill[bucketOf[static_cast<std::size_t>(i)]]++;
      slots[k] = {cellOf[static_cast<std::size_t>(i)],
                  {points[3 * static_cast<std::size_t>(i)], points[3 * static_cast<std::size_t>(i) + 1],
                   points[3 * static_cast<std::size_t>(i) + 2]},
                  i};
    }
  }
  // A pair closer than r lies in one cell or in two adjacent ones. Each slot looks in its own cell at the slots
  // after it, and in the 13 adjacent cells that follow its own (lexicographically): every pair is seen once.
  // A bucket may also hold other cells' points (hash collisions): only the looked-for cell's are compared.
  const double r2 = radius * radius;
  const int threads = n >= 4096 ? omp_get_max_threads() : 1;
  std::vector<std::vector<PointPair>> found(static_cast<std::size_t>(threads));
#pragma omp parallel num_threads(threads)
  {
    std::vector<PointPair>& mine = found[static_cast<std::size_t>(omp_get_thread_num())];
    auto consider = [&](const Slot& a, const Slot& b) {
      double d2 = 0.0;
      for (int c = 0; c < 3; ++c) {
        const double d = b.point[static_cast<std::size_t>(c)] - a.point[static_cast<std::size_t>(c)];
        d2 += d * d;
      }
      if (!(d2 < r2)) return;
      const int i = std::min(a.id, b.id), j = std::max(a.id, b.id);
      if (!filter || filter(i, j)) mine.push_back({i, j});
    };
#pragma omp for schedule(static)
    for (int k = 0; k < n; ++k) {
      const Slot& a = slots[static_cast<std::size_t>(k)];
      const std::uint32_t own = bucketOf[static_cast<std::size_t>(a.id)];
      for (std::uint32_t m = static_cast<std::uint32_t>(k) + 1; m < start[own + 1]; ++m)
        if (slots[m].cell == a.cell) consider(a, slots[m]);
      for (const Cell& d : kForward) {
        const Cell target = {a.cell[0] + d[0], a.cell[1] + d[1], a.cell[2] + d[2]};
        const std::uint32_t b = static_cast<std::uint32_t>(cellHash(target) & mask);
        for (std::uint32_t m = start[b]; m < start[b + 1]; ++m)
          if (slots[m].cell == target) consider(a, slots[m]);
      }
    }
  }
  for (const auto& f : found) pairs.insert(pairs.end(), f.begin(), f.end());
  std::sort(pairs.begin(), pairs.end());
  return pairs;
}

}  // namespace jetshell
