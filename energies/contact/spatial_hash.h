// Broad phase for point contact: all pairs of points closer than a search radius, with a spatial hash.
//
// Input: n points (3n flat, or gathered from x by vertex ids), a radius r > 0 and a pair filter. Output: the
// pairs (i < j, indices into the point list) with ‖p_i − p_j‖ < r that the filter accepts, sorted. Points go
// into cells of size r (a counting sort by hashed cell: O(n)); each point looks in its own cell and the 13
// adjacent cells that follow it, so every pair is measured once, in parallel. The sorted output does not depend
// on the thread count. Rebuilt by the caller as points move.
#pragma once

#include <Eigen/Core>

#include <array>
#include <functional>
#include <vector>

namespace jetshell {

using PointPair = std::array<int, 2>;
/// Returns true when the pair (i < j) may interact.
using PairFilter = std::function<bool(int i, int j)>;

/// points: 3n coordinates (point i at 3i). Throws InputError for r ≤ 0 or non-finite coordinates.
std::vector<PointPair> findClosePairs(const std::vector<double>& points, double radius, const PairFilter& filter = {});
/// True when findClosePairs can hash every point for this radius: each coordinate finite and within 1e15 cells of
/// the origin (findClosePairs throws InputError otherwise).
bool hashablePoint(const double* point, double radius);

}  // namespace jetshell
