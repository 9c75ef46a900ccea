#include "solvers/vertex_bisection.h"

#include <cholmod.h>

#include <algorithm>
#include <array>
#include <stdexcept>

namespace jetshell {

std::vector<std::vector<int>> vertexNeighbours(const Eigen::MatrixXi& F, int numVertices) {
  std::vector<std::vector<int>> neighbours(static_cast<std::size_t>(std::max(numVertices, 0)));
  for (int v = 0; v < numVertices; ++v) neighbours[static_cast<std::size_t>(v)].push_back(v);
  for (Eigen::Index f = 0; f < F.rows(); ++f) {
    for (int k = 0; k < 3; ++k) {
      const int a = F(f, k), b = F(f, (k + 1) % 3);
      if (a < 0 || b < 0 || a >= numVertices || b >= numVertices)
        throw std::invalid_argument("vertexNeighbours: triangle vertex out of range");
      neighbours[static_cast<std::size_t>(a)].push_back(b);
      neighbours[static_cast<std::size_t>(b)].push_back(a);
    }
  }
  for (std::vector<int>& n : neighbours) {
    std::sort(n.begin(), n.end());
    n.erase(std::unique(n.begin(), n.end()), n.end());
  }
  return neighbours;
}

std::vector<std::int8_t> bisectVertices(const std::vector<std::vector<int>>& neighbours) {
  const int numVertices = static_cast<int>(neighbours.size());
  std::vector<std::int8_t> part(neighbours.size(), 0);
  if (numVertices < kMinBisectedVertices) return part;
  // The vertex graph as the strict upper triangle of a symmetric pattern (CSC, sorted, no duplicates).
  std::vector<int> colStart(static_cast<std::size_t>(numVertices) + 1, 0), rows;
  for (int j = 0; j < numVertices; ++j) {
    for (int i : neighbours[static_cast<std::size_t>(j)])
      if (i < j) rows.push_back(i);
    colStart[static_cast<std::size_t>(j) + 1] = static_cast<int>(rows.size());
  }
  if (rows.empty()) return part;

  cholmod_common common;
  cholmod_start(&common);
  common.print = 0;
  cholmod_sparse A{};
  A.nrow = A.ncol = static_cast<std::size_t>(numVertices);
  A.nzmax = rows.size();
  A.p = colStart.data();
  A.i = rows.data();
  A.stype = 1;  // the upper triangle of a symmetric matrix
  A.itype = CHOLMOD_INT;
  A.xtype = CHOLMOD_PATTERN;
  A.dtype = CHOLMOD_DOUBLE;
  A.sorted = 1;
  A.packed = 1;
  std::vector<int> partition(static_cast<std::size_t>(numVertices), 0);
  const SuiteSparse_long separator = cholmod_bisect(&A, nullptr, 0, 1, partition.data(), &common);
  const bool ok = separator >= 0 && common.status == CHOLMOD_OK;
  cholmod_finish(&common);
  if (!ok) return part;

  std::array<int, 2> size{0, 0};
  for (int p : partition)
    if (p == 0 || p == 1) ++size[static_cast<std::size_t>(p)];
  if (size[0] == 0 || size[1] == 0) return part;  // nothing to run side by side
  for (int v = 0; v < numVertices; ++v) {
    const int p = partition[static_cast<std::size_t>(v)];
    if (p == 0 || p == 1) part[static_cast<std::size_t>(v)] = static_cast<std::int8_t>(p);
  }
  // Separator vertices, in index order: each joins the smaller part (the two factors then cost about the same;
  // the couplings cut are the separator's edges to the other part either way).
  for (int v = 0; v < numVertices; ++v) {
    if (partition[static_cast<std::size_t>(v)] != 2) continue;
    const int p = size[0] <= size[1] ? 0 : 1;
    part[static_cast<std::size_t>(v)] = static_cast<std::int8_t>(p);
    ++size[static_cast<std::size_t>(p)];
  }
  return part;
}

}  // namespace jetshell
