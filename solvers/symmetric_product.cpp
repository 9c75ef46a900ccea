#include "solvers/symmetric_product.h"

#include <algorithm>
#include <cmath>

namespace jetshell {
namespace {

/// Columns per chunk are chosen so a chunk holds about this many nonzeros: large enough that the scatter
/// buffers stay few, small enough for several chunks per thread.
constexpr Eigen::Index kChunkNonZeros = 1 << 16;

/// Whether columns j, j+1, j+2 are one vertex's: the same rows above j in all three (the blocks of the vertices
/// before it), then the diagonal block's upper triangle (j; j, j+1; j, j+1, j+2). The shape alone (the
/// columns' lengths and their diagonal blocks) is a few reads; the rows above are compared only by
/// vertexColumns.
bool vertexColumnsShape(const int* outer, const int* inner, Eigen::Index j) {
  const int b = outer[j + 1], c = outer[j + 2], d = outer[j + 3];
  const int m = b - outer[j] - 1;  // rows above j
  if (m < 0 || c - b != m + 2 || d - c != m + 3) return false;
  const auto row = static_cast<int>(j);
  return inner[b - 1] == row && inner[c - 2] == row && inner[c - 1] == row + 1 && inner[d - 3] == row &&
         inner[d - 2] == row + 1 && inner[d - 1] == row + 2;
}

bool vertexColumns(const int* outer, const int* inner, Eigen::Index j) {
  if (!vertexColumnsShape(outer, inner, j)) return false;
  const int a = outer[j], b = outer[j + 1], c = outer[j + 2];
  const int m = b - a - 1;
  return std::equal(inner + a, inner + a + m, inner + b) && std::equal(inner + a, inner + a + m, inner + c);
}

/// Column j's row-side sum into y[j] and its column-side terms into s (rows below j).
template <bool Absolute>
void column(const int* outer, const int* inner, const double* value, const double* p, double* y, double* s,
            Eigen::Index j) {
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

/// Columns j, j+1, j+2 of one vertex (vertexColumns) in one pass over their shared rows: each row's index and
/// p_i read once, its scatter entry read and written once. Every sum adds its terms in the order column()
/// would.
template <bool Absolute>
void columnTriple(const int* outer, const int* inner, const double* value, const double* p, double* y, double* s,
                  Eigen::Index j) {
  const int a = outer[j], b = outer[j + 1], c = outer[j + 2];
  const int m = b - a - 1;
  const double* h0 = value + a;
  const double* h1 = value + b;
  const double* h2 = value + c;
  const auto mag = [](double v) { return Absolute ? std::abs(v) : v; };
  const double p0 = p[j], p1 = p[j + 1], p2 = p[j + 2];
  double row0 = 0.0, row1 = 0.0, row2 = 0.0;
  for (int k = 0; k < m; ++k) {
    const int i = inner[a + k];
    const double pi = p[i];
    const double g0 = mag(h0[k]), g1 = mag(h1[k]), g2 = mag(h2[k]);
    row0 += g0 * pi;
    row1 += g1 * pi;
    row2 += g2 * pi;
    double si = s[i];
    si += g0 * p0;
    si += g1 * p1;
    si += g2 * p2;
    s[i] = si;
  }
  // The diagonal block, in column order: (j,j); (j,j+1), (j+1,j+1); (j,j+2), (j+1,j+2), (j+2,j+2).
  const double d00 = mag(h0[m]), d01 = mag(h1[m]), d11 = mag(h1[m + 1]);
  const double d02 = mag(h2[m]), d12 = mag(h2[m + 1]), d22 = mag(h2[m + 2]);
  row0 += d00 * p0;
  y[j] = row0;
  row1 += d01 * p0;
  s[j] += d01 * p1;
  row1 += d11 * p1;
  y[j + 1] = row1;
  row2 += d02 * p0;
  s[j] += d02 * p2;
  row2 += d12 * p1;
  s[j + 1] += d12 * p2;
  row2 += d22 * p2;
  y[j + 2] = row2;
}

}  // namespace

void SymmetricProduct::prepare(const Eigen::SparseMatrix<double>& upper) {
  const Eigen::Index n = upper.cols();
  const int* outer = upper.outerIndexPtr();
  chunks_.clear();
  Eigen::Index begin = 0;
  while (begin < n) {
    // Whole vertices (three columns) per chunk, so the triples of columnTriple stay together.
    Eigen::Index end = std::min<Eigen::Index>(begin + 3, n);
    while (end + 3 <= n && outer[end + 3] - outer[begin] <= kChunkNonZeros) end += 3;
    if (n - end < 3) end = n;
    Chunk c;
    c.begin = begin;
    c.end = end;
    chunks_.push_back(std::move(c));
    begin = end;
  }
  cols_ = n;
  nonZeros_ = upper.nonZeros();
}

void SymmetricProduct::apply(const Eigen::SparseMatrix<double>& upper, const Eigen::VectorXd& p, Eigen::VectorXd& y,
                             std::uint64_t patternVersion) {
  product<false>(upper, p, y, patternVersion);
}

void SymmetricProduct::applyAbsolute(const Eigen::SparseMatrix<double>& upper, const Eigen::VectorXd& p,
                                     Eigen::VectorXd& y) {
  product<true>(upper, p, y, 0);
}

template <bool Absolute>
void SymmetricProduct::product(const Eigen::SparseMatrix<double>& upper, const Eigen::VectorXd& p,
                               Eigen::VectorXd& y, std::uint64_t patternVersion) {
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
  // Which columns start a vertex: compared in full once per pattern version (0: on every call), then only their
  // shape is looked at again.
  const bool known = patternVersion != 0 && patternVersion == checkedVersion_ &&
                     static_cast<Eigen::Index>(vertexStart_.size()) == n;
  const bool record = patternVersion != 0 && !known;
  if (record) vertexStart_.assign(static_cast<std::size_t>(n), 0);
  char* starts = vertexStart_.data();
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
      Eigen::Index j = chunk.begin;
      while (j < chunk.end) {
        bool triple = false;
        if (j + 2 < chunk.end) {
          if (known) {
            triple = starts[j] && vertexColumnsShape(outer, inner, j);
          } else {
            triple = vertexColumns(outer, inner, j);
            if (record) starts[j] = triple;
          }
        }
        if (triple) {
          columnTriple<Absolute>(outer, inner, value, p.data(), y.data(), s, j);
          j += 3;
          continue;
        }
        column<Absolute>(outer, inner, value, p.data(), y.data(), s, j);
        ++j;
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
  if (record) checkedVersion_ = patternVersion;
}

}  // namespace jetshell
