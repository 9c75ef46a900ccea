#include "tools/scene/open_seams.h"

#include "tools/scene/near_pairs.h"

#include <algorithm>
#include <numeric>
#include <string>
#include <utility>

namespace jetshell {

OpenSeams findOpenSeams(const TriMesh& mesh, const Topology& topology) {
  OpenSeams seams;
  const int edges = topology.numEdges();
  if (edges == 0) return seams;
  const double h = kOpenSeamTolerance * meanEdgeLength(mesh, topology);
  seams.tolerance = h;
  if (!(h > 0.0)) return seams;
  // Edges as sorted (smaller, larger) pairs: two vertices an edge joins make a short edge, not a seam.
  std::vector<std::array<int, 2>> joined(static_cast<std::size_t>(edges));
  for (int e = 0; e < edges; ++e) joined[static_cast<std::size_t>(e)] = {topology.edges(e, 0), topology.edges(e, 1)};
  std::sort(joined.begin(), joined.end());
  // At most kOpenSeamPairs pairs a vertex are kept (a seam vertex has one or two partners): a mesh of thousands of
  // copies of one point stops the search there rather than filling memory.
  const std::size_t most = static_cast<std::size_t>(kOpenSeamPairs) * static_cast<std::size_t>(mesh.numVertices());
  const bool complete = visitNearPairs(
      mesh.V, h,
      [&](int v, int w) {
        if (std::binary_search(joined.begin(), joined.end(), std::array<int, 2>{v, w})) return true;
        seams.pairs.push_back({v, w});
        return seams.pairs.size() < most;
      },
      kOpenSeamVisits);
  seams.partial = !complete;
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
