#include "solvers/symmetric_product.h"

#include <algorithm>
#include <cmath>

namespace jetshell {
namespace {

/// Columns per chunk are chosen so a chunk holds about this many nonzeros: large enough that the scatter
/// buffers stay few, small enough for several chunks per thread.
constexpr Eigen::Index kChunkNonZeros = 1 << 16;

}  // namespace

void SymmetricProduct::prepare(const Eigen::SparseMatrix<double>& upper) {
  const Eigen::Index n = upper.cols();
  const int* outer = upper.outerIndexPtr();
  chunks_.clear();
  Eigen::Index begin = 0;
  while (begin < n) {
    Eigen::Index end = begin + 1;
    while (end < n && outer[end + 1] - outer[begin] <= kChunkNonZeros) ++end;
    Chunk c;
    c.begin = begin;
    c.end = end;
    chunks_.push_back(std::move(c));
    begin = end;
  }
  cols_ = n;
  nonZeros_ = upper.nonZeros();
}

void SymmetricProduct::apply(const Eigen::SparseMatrix<double>& upper, const Eigen::VectorXd& p,
                             Eigen::VectorXd& y) {
  product<false>(upper, p, y);
}

void SymmetricProduct::applyAbsolute(const Eigen::SparseMatrix<double>& upper, const Eigen::VectorXd& p,
                                     Eigen::VectorXd& y) {
  product<true>(upper, p, y);
}

template <bool Absolute>
void SymmetricProduct::product(const Eigen::SparseMatrix<double>& upper, const Eigen::VectorXd& p,
                               Eigen::VectorXd& y) {
  if (!upper.isCompressed()) {
    if constexpr (Absolute) {
      const Eigen::SparseMatrix<double> magnitudes = upper.cwiseAbs();
      y = magnitudes.selfadjointView<Eigen::Upper>() * p;
    } else {
      y = upper.selfadjointView<Eigen::Upper>() * p;
    }
    return;
  }
  if (upper.cols() != cols_ || upper.nonZeros() != nonZeros_) prepare(upper);
  const Eigen::Index n = upper.cols();
  y.resize(n);
  const int* outer = upper.outerIndexPtr();
  const int* inner = upper.innerIndexPtr();
  const double* value = upper.valuePtr();
  const int numChunks = static_cast<int>(chunks_.size());
#pragma omp parallel if (numChunks > 1)
  {
#pragma omp for schedule(dynamic, 1)
    for (int c = 0; c < numChunks; ++c) {
      Chunk& chunk = chunks_[static_cast<std::size_t>(c)];
      // The rows this chunk reaches depend on the pattern, which may change between calls with the same size:
      // found on every call (one look per column, against a pass over the chunk's entries below).
      chunk.firstRow = chunk.begin;
      for (Eigen::Index j = chunk.begin; j < chunk.end; ++j) {
        if (outer[j + 1] > outer[j]) chunk.firstRow = std::min<Eigen::Index>(chunk.firstRow, inner[outer[j]]);
      }
      chunk.scatter.assign(static_cast<std::size_t>(chunk.end - chunk.firstRow), 0.0);
      double* s = chunk.scatter.data() - chunk.firstRow;
      for (Eigen::Index j = chunk.begin; j < chunk.end; ++j) {
        const double pj = p[j];
        double row = 0.0;
        for (int k = outer[j]; k < outer[j + 1]; ++k) {
          const int i = inner[k];
          const double h = Absolute ? std::abs(value[k]) : value[k];
          row += h * p[i];
          if (i != j) s[i] += h * pj;
        }
        y[j] = row;
      }
    }
    // Buffers into y, each row summing the chunks that reach it in chunk order.
#pragma omp for schedule(static)
    for (int c = 0; c < numChunks; ++c) {
      const Chunk& mine = chunks_[static_cast<std::size_t>(c)];
      for (Eigen::Index i = mine.begin; i < mine.end; ++i) {
        double sum = y[i];
        for (int d = c; d < numChunks; ++d) {
          const Chunk& other = chunks_[static_cast<std::size_t>(d)];
          if (other.firstRow <= i) sum += other.scatter[static_cast<std::size_t>(i - other.firstRow)];
        }
        y[i] = sum;
      }
    }
  }
}

}  // namespace jetshell
