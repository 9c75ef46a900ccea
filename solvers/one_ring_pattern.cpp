#include "solvers/one_ring_pattern.h"

#include "solvers/vertex_bisection.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace jetshell {

OneRingFilter::OneRingFilter(const Eigen::MatrixXi& F, int numVertices, int parts)
    : neighbours_(static_cast<std::size_t>(numVertices)) {
  if (parts != 1 && parts != 2) throw std::invalid_argument("OneRingFilter: parts must be 1 or 2");
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
  if (parts == 2) {
    part_ = bisectVertices(F, numVertices);
    if (std::none_of(part_.begin(), part_.end(), [](std::int8_t p) { return p != 0; })) part_.clear();
  }
}

bool OneRingFilter::adjacent(int a, int b) const {
  if (!part_.empty() && part_[static_cast<std::size_t>(a)] != part_[static_cast<std::size_t>(b)]) return false;
  const std::vector<int>& n = neighbours_[static_cast<std::size_t>(a)];
  return std::binary_search(n.begin(), n.end(), b);
}

void OneRingFilter::apply(const Eigen::SparseMatrix<double>& upper, Eigen::SparseMatrix<double>& out) const {
  OneRingPlan plan;
  plan.plan(*this, upper);
  out = plan.apply(upper);
}

void OneRingPlan::plan(const OneRingFilter& filter, const Eigen::SparseMatrix<double>& upper) {
  const Eigen::Index n = upper.rows();
  if (upper.cols() != n || n != 3 * static_cast<Eigen::Index>(filter.numVertices()) || !upper.isCompressed())
    throw std::invalid_argument("OneRingFilter: matrix size does not match the mesh");
  const int* outer = upper.outerIndexPtr();
  const int* inner = upper.innerIndexPtr();
  kept_.clear();
  dropped_.clear();
  droppedRow_.clear();
  droppedCol_.clear();
  diagonal_.assign(static_cast<std::size_t>(n), -1);
  std::vector<int> start(static_cast<std::size_t>(n) + 1, 0);
  kept_.reserve(static_cast<std::size_t>(upper.nonZeros()));
  for (Eigen::Index j = 0; j < n; ++j) {
    // A column's rows come in runs of one row vertex (3 entries): one adjacency search per run.
    int runVertex = -1;
    bool runAdjacent = false;
    for (int p = outer[j]; p < outer[j + 1]; ++p) {
      if (inner[p] / 3 != runVertex) {
        runVertex = inner[p] / 3;
        runAdjacent = filter.adjacent(runVertex, static_cast<int>(j / 3));
      }
      if (!runAdjacent) {
        dropped_.push_back(p);
        droppedRow_.push_back(inner[p]);
        droppedCol_.push_back(static_cast<int>(j));
        continue;
      }
      if (inner[p] == j) diagonal_[static_cast<std::size_t>(j)] = static_cast<int>(kept_.size());
      kept_.push_back(p);
    }
    start[static_cast<std::size_t>(j) + 1] = static_cast<int>(kept_.size());
  }
  for (std::size_t k = 0; k < dropped_.size(); ++k) {
    for (int row : {droppedCol_[k], droppedRow_[k]}) {
      if (diagonal_[static_cast<std::size_t>(row)] < 0)
        throw std::invalid_argument("OneRingFilter: the matrix lacks a diagonal entry");
    }
  }
  result_.resize(n, n);
  result_.resizeNonZeros(static_cast<Eigen::Index>(kept_.size()));
  std::copy(start.begin(), start.end(), result_.outerIndexPtr());
  int* oi = result_.innerIndexPtr();
  for (std::size_t q = 0; q < kept_.size(); ++q) oi[q] = inner[kept_[q]];
  droppedSum_.assign(static_cast<std::size_t>(n), 0.0);
  cols_ = n;
  nonZeros_ = upper.nonZeros();
  planned_ = true;
}

const Eigen::SparseMatrix<double>& OneRingPlan::apply(const Eigen::SparseMatrix<double>& upper) {
  if (!planned_ || upper.cols() != cols_ || upper.nonZeros() != nonZeros_)
    throw std::invalid_argument("OneRingPlan::apply: the matrix's pattern is not the planned one");
  const double* value = upper.valuePtr();
  double* ov = result_.valuePtr();
  const std::size_t kept = kept_.size();
  for (std::size_t q = 0; q < kept; ++q) ov[q] = value[kept_[q]];
  std::fill(droppedSum_.begin(), droppedSum_.end(), 0.0);
  for (std::size_t k = 0; k < dropped_.size(); ++k) {
    const double a = std::abs(value[dropped_[k]]);
    droppedSum_[static_cast<std::size_t>(droppedCol_[k])] += a;
    droppedSum_[static_cast<std::size_t>(droppedRow_[k])] += a;
  }
  for (std::size_t j = 0; j < droppedSum_.size(); ++j) {
    if (droppedSum_[j] != 0.0) ov[diagonal_[j]] += droppedSum_[j];
  }
  return result_;
}

}  // namespace jetshell

