// Pairs of points nearer than a radius, for the scene reader's checks (open seams, layers that start in contact):
// serial, since the reader is part of the parser library, which runs without threads (the contact broad phase,
// energies/contact/spatial_hash.h, is its threaded counterpart for the solver).
//
// The points are sorted by the cell of the radius's size they fall in; each looks in the 27 cells around it,
// behind a one-bit-a-cell filter of the occupied cells that spares the search of nearly every empty one:
// O(n log n). The search visits at most visitsPerPoint × n points in all, so that thousands of points crowded
// into one cell cost bounded time; past that budget it stops and says so.
#pragma once

#include "core/mesh.h"

#include <functional>

namespace jetshell {

/// Calls visit(i, j), i < j, for each pair of the points (N × 3) nearer than `radius` (> 0), in no set order;
/// visit returns false to stop the search. Returns true when every pair was visited, false when the search stopped:
/// at its budget, at visit's word, or at a coordinate over 1e15 radii from the origin (the cells cannot hold it).
/// Nothing is stored per pair: the caller keeps what it needs, and bounds it.
bool visitNearPairs(const Positions& points, double radius, const std::function<bool(int, int)>& visit,
                    long long visitsPerPoint);

}  // namespace jetshell
