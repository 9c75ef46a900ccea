#include "energies/contact/spatial_hash.h"

#include "core/mesh.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <omp.h>

namespace jetshell {
namespace {

std::uint64_t cellHash(std::int64_t x, std::int64_t y, std::int64_t z) {
  std::uint64_t h = static_cast<std::uint64_t>(x) * 0x9E3779B97F4A7C15ull;
  h ^= static_cast<std::uint64_t>(y) * 0xC2B2AE3D27D4EB4Full + (h << 6) + (h >> 2);
  h ^= static_cast<std::uint64_t>(z) * 0x165667B19E3779F9ull + (h << 6) + (h >> 2);
  return h ^ (h >> 29);
}

}  // namespace

std::vector<PointPair> findClosePairs(const std::vector<double>& points, double radius, const PairFilter& filter) {
  if (!(std::isfinite(radius) && radius > 0.0)) throw InputError("broad phase: radius must be finite and > 0");
  const int n = static_cast<int>(points.size() / 3);
  std::vector<PointPair> pairs;
  if (n < 2) return pairs;
  std::size_t buckets = 1;
  while (buckets < 2 * static_cast<std::size_t>(n)) buckets <<= 1;
  const std::uint64_t mask = buckets - 1;
  const double inv = 1.0 / radius;
  std::vector<std::int64_t> cell(3 * static_cast<std::size_t>(n));
  std::vector<std::uint32_t> bucketOf(static_cast<std::size_t>(n));
  bool finite = true;
#pragma omp parallel for schedule(static) reduction(&& : finite) if (n >= 4096)
  for (int i = 0; i < n; ++i) {
    for (int c = 0; c < 3; ++c) {
      const double v = points[3 * static_cast<std::size_t>(i) + c] * inv;
      finite = finite && std::isfinite(v) && std::abs(v) < 1e15;
      cell[3 * static_cast<std::size_t>(i) + c] = std::isfinite(v) ? static_cast<std::int64_t>(std::floor(v)) : 0;
    }
    bucketOf[i] = static_cast<std::uint32_t>(
        cellHash(cell[3 * static_cast<std::size_t>(i)], cell[3 * static_cast<std::size_t>(i) + 1],
                 cell[3 * static_cast<std::size_t>(i) + 2]) & mask);
  }
  if (!finite) throw InputError("broad phase: non-finite or huge point coordinates");
  // Counting sort of the points by bucket.
  std::vector<std::uint32_t> start(buckets + 1, 0), order(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) ++start[bucketOf[i] + 1];
  for (std::size_t b = 0; b < buckets; ++b) start[b + 1] += start[b];
  {
    std::vector<std::uint32_t> fill(start.begin(), start.end() - 1);
    for (int i = 0; i < n; ++i) order[fill[bucketOf[i]]++] = static_cast<std::uint32_t>(i);
  }
  const double r2 = radius * radius;
  const int threads = n >= 4096 ? omp_get_max_threads() : 1;
  std::vector<std::vector<PointPair>> found(static_cast<std::size_t>(threads));
#pragma omp parallel num_threads(threads)
  {
    std::vector<PointPair>& mine = found[static_cast<std::size_t>(omp_get_thread_num())];
    std::uint32_t visited[27];
#pragma omp for schedule(static)
    for (int i = 0; i < n; ++i) {
      const std::int64_t* ci = &cell[3 * static_cast<std::size_t>(i)];
      int nv = 0;
      for (int dx = -1; dx <= 1; ++dx)
        for (int dy = -1; dy <= 1; ++dy)
          for (int dz = -1; dz <= 1; ++dz) {
            const std::uint32_t b = static_cast<std::uint32_t>(cellHash(ci[0] + dx, ci[1] + dy, ci[2] + dz) & mask);
            if (std::find(visited, visited + nv, b) != visited + nv) continue;  // two cells in one bucket
            visited[nv++] = b;
            for (std::uint32_t k = start[b]; k < start[b + 1]; ++k) {
              const int j = static_cast<int>(order[k]);
              if (j <= i) continue;
              double d2 = 0.0;
              for (int c = 0; c < 3; ++c) {
                const double d = points[3 * static_cast<std::size_t>(j) + c] - points[3 * static_cast<std::size_t>(i) + c];
                d2 += d * d;
              }
              if (d2 < r2 && (!filter || filter(i, j))) mine.push_back({i, j});
            }
          }
    }
  }
  for (const auto& f : found) pairs.insert(pairs.end(), f.begin(), f.end());
  std::sort(pairs.begin(), pairs.end());
  return pairs;
}

}  // namespace jetshell
