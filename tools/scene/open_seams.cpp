#include "tools/scene/open_seams.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numeric>
#include <string>
#include <utility>

namespace jetshell {

OpenSeams findOpenSeams(const TriMesh& mesh, const Topology& topology) {
  OpenSeams seams;
  const int edges = topology.numEdges(), n = mesh.numVertices();
  if (edges == 0) return seams;
  double total = 0.0;
  for (int e = 0; e < edges; ++e) total += (mesh.V.row(topology.edges(e, 0)) - mesh.V.row(topology.edges(e, 1))).norm();
  const double h = kOpenSeamTolerance * total / edges;
  seams.tolerance = h;
  if (!(h > 0.0)) return seams;
  // Each vertex's cell of size h, and the vertices sorted by cell: the vertices of a cell are one run.
  using Cell = std::array<std::int64_t, 3>;
  std::vector<std::pair<Cell, int>> sorted(static_cast<std::size_t>(n));
  for (int v = 0; v < n; ++v) {
    Cell c{};
    for (int k = 0; k < 3; ++k) {
      const double q = std::floor(mesh.V(v, k) / h);
      if (!(std::abs(q) < 1e15)) {
        seams.partial = true;
        return seams;
      }
      c[static_cast<std::size_t>(k)] = static_cast<std::int64_t>(q);
    }
    sorted[static_cast<std::size_t>(v)] = {c, v};
  }
  std::sort(sorted.begin(), sorted.end());
  // A filter of the occupied cells (one bit per hashed cell, 8 bits a vertex): cells are a thousandth of an edge,
  // so nearly every cell looked in is empty, and the filter answers for it without a binary search.
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
  // Edges as sorted (smaller, larger) pairs: two vertices an edge joins make a short edge, not a seam.
  std::vector<std::array<int, 2>> joined(static_cast<std::size_t>(edges));
  for (int e = 0; e < edges; ++e) joined[static_cast<std::size_t>(e)] = {topology.edges(e, 0), topology.edges(e, 1)};
  std::sort(joined.begin(), joined.end());
  long long budget = kOpenSeamVisits * n;
  // Vertex v against the later vertices of one cell; false once the budget (vertices visited) is spent.
  auto compare = [&](int v, const Cell& cell) {
    if (const std::uint64_t b = bit(cell); !(occupied[b / 64] >> (b % 64) & 1)) return true;
    for (auto it = std::lower_bound(sorted.begin(), sorted.end(), std::make_pair(cell, -1));
         it != sorted.end() && it->first == cell; ++it) {
      if (--budget < 0) return false;
      const int w = it->second;
      if (w <= v || (mesh.V.row(v) - mesh.V.row(w)).norm() >= h) continue;
      const std::array<int, 2> pair{v, w};
      if (!std::binary_search(joined.begin(), joined.end(), pair)) seams.pairs.push_back(pair);
    }
    return true;
  };
  for (std::size_t k = 0; k < sorted.size() && !seams.partial; ++k) {
    const auto& [cell, v] = sorted[k];
    for (int d = 0; d < 27 && !seams.partial; ++d)
      seams.partial = !compare(v, {cell[0] + d % 3 - 1, cell[1] + d / 3 % 3 - 1, cell[2] + d / 9 - 1});
  }
  std::sort(seams.pairs.begin(), seams.pairs.end());
  std::vector<int> ids;
  ids.reserve(2 * seams.pairs.size());
  for (const auto& p : seams.pairs) ids.insert(ids.end(), p.begin(), p.end());
  std::sort(ids.begin(), ids.end());
  seams.vertices = static_cast<int>(std::unique(ids.begin(), ids.end()) - ids.begin());
  return seams;
}

TriMesh weldOpenSeams(const TriMesh& mesh, const OpenSeams& seams, const std::string& where) {
  if (seams.partial)
    throw InputError(where + ": cannot weld: too many vertices lie within the tolerance of one another for a search " +
                     "of " + std::to_string(kOpenSeamVisits) + " visits a vertex (or a coordinate is over 1e15 " +
                     "tolerances from the origin)");
  // Union-find over the pairs; each group's root is its smallest id.
  std::vector<int> root(static_cast<std::size_t>(mesh.numVertices()));
  std::iota(root.begin(), root.end(), 0);
  auto find = [&](int v) {
    while (root[static_cast<std::size_t>(v)] != v)
      v = root[static_cast<std::size_t>(v)] = root[static_cast<std::size_t>(root[static_cast<std::size_t>(v)])];
    return v;
  };
  for (const auto& [a, b] : seams.pairs) {
    const int ra = find(a), rb = find(b);
    root[static_cast<std::size_t>(std::max(ra, rb))] = std::min(ra, rb);
  }
  std::vector<int> newId(root.size(), -1);
  int kept = 0;
  for (int v = 0; v < mesh.numVertices(); ++v)
    if (find(v) == v) newId[static_cast<std::size_t>(v)] = kept++;
  TriMesh welded;
  welded.V.resize(kept, 3);
  for (int v = 0; v < mesh.numVertices(); ++v)
    if (newId[static_cast<std::size_t>(v)] >= 0) welded.V.row(newId[static_cast<std::size_t>(v)]) = mesh.V.row(v);
  welded.F.resize(mesh.numFaces(), 3);
  for (int f = 0; f < mesh.numFaces(); ++f)
    for (int c = 0; c < 3; ++c) welded.F(f, c) = newId[static_cast<std::size_t>(find(mesh.F(f, c)))];
  return welded;
}

}  // namespace jetshell
