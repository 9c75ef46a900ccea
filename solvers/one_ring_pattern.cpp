#include "solvers/one_ring_pattern.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace jetshell {

OneRingFilter::OneRingFilter(const Eigen::MatrixXi& F, int numVertices)
    : neighbours_(static_cast<std::size_t>(numVertices)) {
  for (int v = 0; v < numVertices; ++v) neighbours_[static_cast<std::size_t>(v)].push_back(v);
  for (Eigen::Index f = 0; f < F.rows(); ++f) {
    for (int k = 0; k < 3; ++k) {
      const int a = F(f, k), b = F(f, (k + 1) % 3);
      if (a < 0 || b < 0 || a >= numVertices || b >= numVertices)
        throw std::invalid_argument("OneRingFilter: triangle vertex out of range");
      neighbours_[static_cast<std::size_t>(a)].push_back(b);
      neighbours_[static_cast<std::size_t>(b)].push_back(a);
    }
  }
  for (std::vector<int>& n : neighbours_) {
    std::sort(n.begin(), n.end());
    n.erase(std::unique(n.begin(), n.end()), n.end());
  }
}

bool OneRingFilter::adjacent(int a, int b) const {
  const std::vector<int>& n = neighbours_[static_cast<std::size_t>(a)];
  return std::binary_search(n.begin(), n.end(), b);
}

void OneRingFilter::apply(const Eigen::SparseMatrix<double>& upper, Eigen::SparseMatrix<double>& out) const {
  const Eigen::Index n = upper.rows();
  if (upper.cols() != n || n != 3 * static_cast<Eigen::Index>(neighbours_.size()) || !upper.isCompressed())
    throw std::invalid_argument("OneRingFilter::apply: matrix size does not match the mesh");
  const int* outer = upper.outerIndexPtr();
  const int* inner = upper.innerIndexPtr();
  const double* value = upper.valuePtr();
  // Count, then fill (CSC, rows sorted as in the input).
  std::vector<int> start(static_cast<std::size_t>(n) + 1, 0);
  for (Eigen::Index j = 0; j < n; ++j) {
    int count = 0;
    for (int p = outer[j]; p < outer[j + 1]; ++p)
      if (adjacent(inner[p] / 3, static_cast<int>(j / 3))) ++count;
    start[static_cast<std::size_t>(j) + 1] = start[static_cast<std::size_t>(j)] + count;
  }
  out.resize(n, n);
  out.resizeNonZeros(start.back());
  std::copy(start.begin(), start.end(), out.outerIndexPtr());
  int* oi = out.innerIndexPtr();
  double* ov = out.valuePtr();
  std::vector<double> dropped(static_cast<std::size_t>(n), 0.0);  // Σ |dropped entries| per row
  std::vector<int> diagonal(static_cast<std::size_t>(n), -1);
  for (Eigen::Index j = 0; j < n; ++j) {
    int q = start[static_cast<std::size_t>(j)];
    for (int p = outer[j]; p < outer[j + 1]; ++p) {
      if (!adjacent(inner[p] / 3, static_cast<int>(j / 3))) {
        dropped[static_cast<std::size_t>(j)] += std::abs(value[p]);
        dropped[static_cast<std::size_t>(inner[p])] += std::abs(value[p]);
        continue;
      }
      if (inner[p] == j) diagonal[static_cast<std::size_t>(j)] = q;
      oi[q] = inner[p];
      ov[q] = value[p];
      ++q;
    }
  }
  // Diagonal compensation: H − H_kept is dominated by the diagonal of its absolute row sums, so
  // H_kept + diag(dropped) ⪰ H stays positive definite whenever H is.
  for (Eigen::Index j = 0; j < n; ++j) {
    if (dropped[static_cast<std::size_t>(j)] == 0.0) continue;
    if (diagonal[static_cast<std::size_t>(j)] < 0)
      throw std::invalid_argument("OneRingFilter::apply: the matrix lacks a diagonal entry");
    ov[diagonal[static_cast<std::size_t>(j)]] += dropped[static_cast<std::size_t>(j)];
  }
}

}  // namespace jetshell
