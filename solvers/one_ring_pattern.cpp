#include "solvers/one_ring_pattern.h"

#include "solvers/vertex_bisection.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace jetshell {

OneRingFilter::OneRingFilter(const Eigen::MatrixXi& F, int numVertices, int parts)
    : neighbours_(vertexNeighbours(F, numVertices)) {
  if (parts != 1 && parts != 2) throw std::invalid_argument("OneRingFilter: parts must be 1 or 2");
  if (parts == 2) {
    part_ = bisectVertices(neighbours_);
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
  const auto cols = static_cast<std::size_t>(n);
  const auto nnz = static_cast<std::size_t>(upper.nonZeros());
  // Pass 1, by column on the threads: which entries stay (one adjacency search per run of a row vertex's three
  // entries), and each column's counts.
  keep_.resize(nnz);
  std::vector<int> keptIn(cols + 1, 0), droppedIn(cols + 1, 0), droppedInRow(cols + 1, 0);
#pragma omp parallel for schedule(dynamic, 256)
  for (Eigen::Index j = 0; j < n; ++j) {
    int runVertex = -1;
    bool runAdjacent = false;
    int kept = 0;
    for (int p = outer[j]; p < outer[j + 1]; ++p) {
      if (inner[p] / 3 != runVertex) {
        runVertex = inner[p] / 3;
        runAdjacent = filter.adjacent(runVertex, static_cast<int>(j / 3));
      }
      keep_[static_cast<std::size_t>(p)] = runAdjacent ? 1 : 0;
      kept += runAdjacent ? 1 : 0;
    }
    keptIn[static_cast<std::size_t>(j) + 1] = kept;
    droppedIn[static_cast<std::size_t>(j) + 1] = outer[j + 1] - outer[j] - kept;
  }
  for (std::size_t p = 0; p < nnz; ++p)
    if (!keep_[p]) ++droppedInRow[static_cast<std::size_t>(inner[p]) + 1];
  for (std::size_t j = 0; j < cols; ++j) {
    keptIn[j + 1] += keptIn[j];
    droppedIn[j + 1] += droppedIn[j];
    droppedInRow[j + 1] += droppedInRow[j];
  }
  // Pass 2: the kept entries' sources and rows, each column's dropped entries, and the diagonal's position.
  kept_.resize(static_cast<std::size_t>(keptIn[cols]));
  droppedByColumn_.resize(static_cast<std::size_t>(droppedIn[cols]));
  droppedColumnStart_ = droppedIn;
  diagonal_.assign(cols, -1);
  result_.resize(n, n);
  result_.resizeNonZeros(static_cast<Eigen::Index>(kept_.size()));
  std::copy(keptIn.begin(), keptIn.end(), result_.outerIndexPtr());
  int* resultRow = result_.innerIndexPtr();
#pragma omp parallel for schedule(dynamic, 256)
  for (Eigen::Index j = 0; j < n; ++j) {
    int q = keptIn[static_cast<std::size_t>(j)], d = droppedIn[static_cast<std::size_t>(j)];
    for (int p = outer[j]; p < outer[j + 1]; ++p) {
      if (!keep_[static_cast<std::size_t>(p)]) {
        droppedByColumn_[static_cast<std::size_t>(d++)] = p;
        continue;
      }
      if (inner[p] == j) diagonal_[static_cast<std::size_t>(j)] = q;
      kept_[static_cast<std::size_t>(q)] = p;
      resultRow[q++] = inner[p];
    }
  }
  // The dropped entries by row (in source order within a row), so each dof's sum is one gather of its own.
  droppedByRow_.resize(droppedByColumn_.size());
  droppedRowStart_ = droppedInRow;
  std::vector<int> fill(droppedInRow.begin(), droppedInRow.end() - 1);
  for (int p : droppedByColumn_) droppedByRow_[static_cast<std::size_t>(fill[static_cast<std::size_t>(inner[p])]++)] = p;
  for (std::size_t j = 0; j < cols; ++j) {
    const bool hasDropped = droppedIn[j + 1] > droppedIn[j] || droppedInRow[j + 1] > droppedInRow[j];
    if (hasDropped && diagonal_[j] < 0) throw std::invalid_argument("OneRingFilter: the matrix lacks a diagonal entry");
  }
  cols_ = n;
  nonZeros_ = upper.nonZeros();
  planned_ = true;
}

const Eigen::SparseMatrix<double>& OneRingPlan::apply(const Eigen::SparseMatrix<double>& upper) {
  if (!planned_ || upper.cols() != cols_ || upper.nonZeros() != nonZeros_)
    throw std::invalid_argument("OneRingPlan::apply: the matrix's pattern is not the planned one");
  const double* value = upper.valuePtr();
  double* ov = result_.valuePtr();
  const auto kept = static_cast<std::int64_t>(kept_.size());
#pragma omp parallel
  {
#pragma omp for schedule(static)
    for (std::int64_t q = 0; q < kept; ++q) ov[q] = value[kept_[static_cast<std::size_t>(q)]];
    // Each dof's dropped magnitudes, its column's then its row's, in a fixed order: the same bits on any number
    // of threads. (The loop's implicit barrier above: the diagonal is gathered before it is added to.)
#pragma omp for schedule(static)
    for (Eigen::Index j = 0; j < cols_; ++j) {
      const auto c = static_cast<std::size_t>(j);
      double sum = 0.0;
      for (int k = droppedColumnStart_[c]; k < droppedColumnStart_[c + 1]; ++k)
        sum += std::abs(value[droppedByColumn_[static_cast<std::size_t>(k)]]);
      for (int k = droppedRowStart_[c]; k < droppedRowStart_[c + 1]; ++k)
        sum += std::abs(value[droppedByRow_[static_cast<std::size_t>(k)]]);
      if (sum != 0.0) ov[diagonal_[c]] += sum;
    }
  }
  return result_;
}

}  // namespace jetshell
