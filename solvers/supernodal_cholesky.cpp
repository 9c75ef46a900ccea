#include "solvers/supernodal_cholesky.h"

#include <cholmod.h>

#include <algorithm>
#include <cmath>

#include <Eigen/Core>

// BLAS and LAPACK's Fortran entry points (the trailing arguments are the character arguments' hidden lengths).
extern "C" {
void dsyrk_(const char* uplo, const char* trans, const int* n, const int* k, const double* alpha, const double* a,
            const int* lda, const double* beta, double* c, const int* ldc, std::size_t, std::size_t);
void dgemm_(const char* transa, const char* transb, const int* m, const int* n, const int* k, const double* alpha,
            const double* a, const int* lda, const double* b, const int* ldb, const double* beta, double* c,
            const int* ldc, std::size_t, std::size_t);
void dtrsm_(const char* side, const char* uplo, const char* transa, const char* diag, const int* m, const int* n,
            const double* alpha, const double* a, const int* lda, double* b, const int* ldb, std::size_t,
            std::size_t, std::size_t, std::size_t);
void dpotrf_(const char* uplo, const int* n, double* a, const int* lda, int* info, std::size_t);
}

namespace jetshell {

namespace {

struct Supernodes {
  int count;
  const int* super;  // first column of each supernode, and n at the end
  const int* pi;     // start of each supernode's row indices in s
  const int* px;     // start of each supernode's block in x
  const int* s;      // row indices: the supernode's own columns first, then the rows below, increasing
};

Supernodes supernodes(const cholmod_factor& L) {
  return {static_cast<int>(L.nsuper), static_cast<const int*>(L.super), static_cast<const int*>(L.pi),
          static_cast<const int*>(L.px), static_cast<const int*>(L.s)};
}

}  // namespace

template <class Update>
void SupernodalCholesky::forEachDescendant(const cholmod_factor& L, int t, Update&& update) {
  const Supernodes sn = supernodes(L);
  const int k2 = sn.super[t + 1];
  int d = head_[static_cast<std::size_t>(t)];
  head_[static_cast<std::size_t>(t)] = -1;
  while (d >= 0) {
    const int following = next_[static_cast<std::size_t>(d)];
    const int dStart = sn.pi[d];
    const int dRows = sn.pi[d + 1] - dStart;
    const int first = position_[static_cast<std::size_t>(d)];
    int end = first;
    while (end < dRows && sn.s[dStart + end] < k2) ++end;
    const int inColumns = end - first;  // rows of d that are columns of t
    const int below = dRows - first;    // rows of d from there to the end
    const auto updateSize = static_cast<std::size_t>(below) * static_cast<std::size_t>(inColumns);
    if (updateSize > update_.size()) update_.resize(updateSize);  // not expected: maxcsize bounds it
    update(d, first, inColumns, below);
    linkDescendant(L, d, end);
    d = following;
  }
}

bool SupernodalCholesky::prepare(const cholmod_factor& L, const Eigen::SparseMatrix<double>& upper,
                                 std::string& message) {
  const auto n = static_cast<std::ptrdiff_t>(L.n);
  if (!L.is_super || L.itype != CHOLMOD_INT || L.Perm == nullptr || upper.rows() != n || upper.cols() != n) {
    message = "supernodal factorization: the factor is not a supernodal analysis of this matrix";
    return false;
  }
  if (!upper.isCompressed()) {
    message = "supernodal factorization: the matrix is not compressed";
    return false;
  }
  const Supernodes sn = supernodes(L);
  const int* perm = static_cast<const int*>(L.Perm);
  std::vector<int> inverse(static_cast<std::size_t>(n));
  for (std::ptrdiff_t k = 0; k < n; ++k) inverse[static_cast<std::size_t>(perm[k])] = static_cast<int>(k);

  superOf_.assign(static_cast<std::size_t>(n), 0);
  diagonal_.assign(static_cast<std::size_t>(n), 0);
  std::size_t widest = 0;  // the most rows of a supernode
  for (int t = 0; t < sn.count; ++t) {
    const int rows = sn.pi[t + 1] - sn.pi[t];
    widest = std::max(widest, static_cast<std::size_t>(rows));
    for (int k = sn.super[t]; k < sn.super[t + 1]; ++k) {
      superOf_[static_cast<std::size_t>(k)] = t;
      diagonal_[static_cast<std::size_t>(k)] = sn.px[t] + static_cast<long>(k - sn.super[t]) * (rows + 1);
    }
  }
  target_.assign(static_cast<std::size_t>(upper.nonZeros()), -1);
  for (std::ptrdiff_t j = 0; j < n; ++j) {
    for (int p = upper.outerIndexPtr()[j]; p < upper.outerIndexPtr()[j + 1]; ++p) {
      const int i = upper.innerIndexPtr()[p];
      if (i > j) continue;  // below the diagonal: not part of the upper triangle (CHOLMOD ignores it too)
      const int a = inverse[static_cast<std::size_t>(i)], b = inverse[static_cast<std::size_t>(j)];
      const int row = std::max(a, b), column = std::min(a, b);
      const int t = superOf_[static_cast<std::size_t>(column)];
      const int* first = sn.s + sn.pi[t];
      const int* last = sn.s + sn.pi[t + 1];
      // The supernode's own columns come first (increasing), then the rows below (increasing).
      const int own = sn.super[t + 1] - sn.super[t];
      const int* at = row < sn.super[t + 1] ? first + (row - sn.super[t]) : std::lower_bound(first + own, last, row);
      if (at == last || *at != row) {
        message = "supernodal factorization: an entry of the matrix is outside the analysed pattern";
        return false;
      }
      target_[static_cast<std::size_t>(p)] =
          sn.px[t] + static_cast<long>(column - sn.super[t]) * (last - first) + (at - first);
    }
  }
  head_.assign(static_cast<std::size_t>(sn.count), -1);
  next_.assign(static_cast<std::size_t>(sn.count), -1);
  position_.assign(static_cast<std::size_t>(sn.count), 0);
  map_.assign(static_cast<std::size_t>(n), 0);
  update_.resize(std::max<std::size_t>(L.maxcsize, 1));  // CHOLMOD's bound on one update block
  permuted_.resize(static_cast<std::size_t>(n));
  rows_.resize(std::max<std::size_t>(widest, 1));
  return true;
}

std::size_t SupernodalCholesky::factorize(cholmod_factor& L, const Eigen::SparseMatrix<double>& upper, double shift) {
  return sweep(L, upper, shift, false);
}

std::size_t SupernodalCholesky::factorizeLdlt(cholmod_factor& L, const Eigen::SparseMatrix<double>& upper) {
  return sweep(L, upper, 0.0, true);
}

std::size_t SupernodalCholesky::sweep(cholmod_factor& L, const Eigen::SparseMatrix<double>& upper, double shift,
                                      bool ldlt) {
  using Column = Eigen::Map<Eigen::VectorXd>;
  using ConstColumn = Eigen::Map<const Eigen::VectorXd>;
  const Supernodes sn = supernodes(L);
  double* x = static_cast<double*>(L.x);
  scatterMatrix(L, upper, shift);
  const double one = 1.0, zero = 0.0;
  for (int t = 0; t < sn.count; ++t) {
    const int k1 = sn.super[t], columns = sn.super[t + 1] - k1;
    const int rowStart = sn.pi[t];
    const int rows = sn.pi[t + 1] - rowStart;
    double* block = x + sn.px[t];
    for (int r = 0; r < rows; ++r) map_[static_cast<std::size_t>(sn.s[rowStart + r])] = r;

    // Updates from the descendants whose next unprocessed row falls in this supernode's columns: −L_d L_dᵀ (a
    // syrk and a gemm) or, for LDLᵀ, −L_d D_d L_dᵀ (one gemm with d's rows in t's columns scaled by d's pivots; a
    // syrk needs a definite D).
    forEachDescendant(L, t, [&](int d, int first, int inColumns, int below) {
      const int dRows = sn.pi[d + 1] - sn.pi[d];
      const int dColumns = sn.super[d + 1] - sn.super[d];
      const double* dBlock = x + sn.px[d] + first;
      double* c = update_.data();
      if (ldlt) {
        const auto scaledSize = static_cast<std::size_t>(inColumns) * static_cast<std::size_t>(dColumns);
        if (scaledSize > scaled_.size()) scaled_.resize(scaledSize);
        for (int k = 0; k < dColumns; ++k) {
          const double pivot = x[sn.px[d] + static_cast<long>(k) * (dRows + 1)];
          Column(scaled_.data() + static_cast<long>(k) * inColumns, inColumns) =
              pivot * ConstColumn(dBlock + static_cast<long>(k) * dRows, inColumns);
        }
        dgemm_("N", "T", &below, &inColumns, &dColumns, &one, dBlock, &dRows, scaled_.data(), &inColumns, &zero, c,
               &below, 1, 1);
      } else {
        dsyrk_("L", "N", &inColumns, &dColumns, &one, dBlock, &dRows, &zero, c, &below, 1, 1);
        if (below > inColumns) {
          const int rest = below - inColumns;
          dgemm_("N", "T", &rest, &inColumns, &dColumns, &one, dBlock + inColumns, &dRows, dBlock, &dRows, &zero,
                 c + inColumns, &below, 1, 1);
        }
      }
      scatterUpdate(block, k1, rows, sn.s + sn.pi[d] + first, c, below, inColumns);
    });

    if (ldlt) {
      // The supernode's own columns, right-looking, each carried down all its rows: column j holds l_ij d_j until
      // the columns after it are updated, then l_ij.
      for (int j = 0; j < columns; ++j) {
        double* cj = block + static_cast<long>(j) * rows;
        const double pivot = cj[j];
        if (pivot == 0.0 || !std::isfinite(pivot)) return static_cast<std::size_t>(k1 + j);
        for (int k = j + 1; k < columns; ++k)
          Column(block + static_cast<long>(k) * rows + k, rows - k) -= (cj[k] / pivot) * ConstColumn(cj + k, rows - k);
        Column(cj + j + 1, rows - j - 1) /= pivot;
      }
    } else {
      int info = 0;
      dpotrf_("L", &columns, block, &rows, &info, 1);
      if (info > 0) return static_cast<std::size_t>(k1 + info - 1);
      for (int k = 0; k < columns; ++k)
        if (!std::isfinite(block[static_cast<long>(k) * (rows + 1)])) return static_cast<std::size_t>(k1 + k);
      if (rows > columns) {
        const int rest = rows - columns;
        dtrsm_("R", "L", "T", "N", &rest, &columns, &one, block, &rows, block + columns, &rows, 1, 1, 1, 1);
      }
    }
    linkDescendant(L, t, columns);
  }
  return L.n;
}

void SupernodalCholesky::scatterMatrix(cholmod_factor& L, const Eigen::SparseMatrix<double>& upper, double shift) {
  double* x = static_cast<double*>(L.x);
  std::fill(x, x + L.xsize, 0.0);
  const double* values = upper.valuePtr();
  for (std::size_t p = 0; p < target_.size(); ++p)
    if (target_[p] >= 0) x[target_[p]] = values[p];
  if (shift != 0.0)
    for (const long d : diagonal_) x[d] += shift;
  std::fill(head_.begin(), head_.end(), -1);
}

void SupernodalCholesky::linkDescendant(const cholmod_factor& L, int t, int position) {
  const Supernodes sn = supernodes(L);
  const int rowStart = sn.pi[t];
  if (position >= sn.pi[t + 1] - rowStart) return;
  position_[static_cast<std::size_t>(t)] = position;
  const int owner = superOf_[static_cast<std::size_t>(sn.s[rowStart + position])];
  next_[static_cast<std::size_t>(t)] = head_[static_cast<std::size_t>(owner)];
  head_[static_cast<std::size_t>(owner)] = t;
}

void SupernodalCholesky::scatterUpdate(double* block, int k1, int rows, const int* rowIndex, const double* c,
                                       int below, int inColumns) {
  for (int j = 0; j < inColumns; ++j) {
    double* column = block + static_cast<long>(rowIndex[j] - k1) * rows;
    const double* cj = c + static_cast<long>(j) * below;
    for (int i = j; i < below; ++i) column[map_[static_cast<std::size_t>(rowIndex[i])]] -= cj[i];
  }
}

void SupernodalCholesky::solve(const cholmod_factor& L, const double* b, double* x) {
  const int* perm = static_cast<const int*>(L.Perm);
  double* y = permuted_.data();
  const auto n = static_cast<int>(L.n);
  for (int k = 0; k < n; ++k) y[k] = b[perm[k]];
  forwardSweep(L, y, false);
  backwardSweep(L, y, false);
  for (int k = 0; k < n; ++k) x[perm[k]] = y[k];
}

void SupernodalCholesky::forwardSweep(const cholmod_factor& L, double* y, bool unit) {
  using Vector = Eigen::Map<Eigen::VectorXd>;
  using ConstVector = Eigen::Map<const Eigen::VectorXd>;
  const Supernodes sn = supernodes(L);
  const double* lx = static_cast<const double*>(L.x);
  double* w = rows_.data();
  // Supernode by supernode: the diagonal block's columns, each carried down its whole column.
  for (int t = 0; t < sn.count; ++t) {
    const int k1 = sn.super[t], columns = sn.super[t + 1] - k1;
    const int* rowIndex = sn.s + sn.pi[t];
    const int rows = sn.pi[t + 1] - sn.pi[t];
    const double* block = lx + sn.px[t];
    for (int j = 0; j < columns; ++j) w[j] = y[k1 + j];
    std::fill(w + columns, w + rows, 0.0);
    for (int j = 0; j < columns; ++j) {
      const double* column = block + static_cast<long>(j) * rows;
      if (!unit) w[j] /= column[j];
      Vector(w + j + 1, rows - j - 1).noalias() -= w[j] * ConstVector(column + j + 1, rows - j - 1);
    }
    for (int j = 0; j < columns; ++j) y[k1 + j] = unit ? w[j] / block[static_cast<long>(j) * (rows + 1)] : w[j];
    for (int i = columns; i < rows; ++i) y[rowIndex[i]] += w[i];
  }
}

void SupernodalCholesky::backwardSweep(const cholmod_factor& L, double* y, bool unit) {
  using ConstVector = Eigen::Map<const Eigen::VectorXd>;
  const Supernodes sn = supernodes(L);
  const double* lx = static_cast<const double*>(L.x);
  double* w = rows_.data();
  // In reverse: each column's dot product with its rows' solution, then (LLᵀ) the diagonal.
  for (int t = sn.count - 1; t >= 0; --t) {
    const int k1 = sn.super[t], columns = sn.super[t + 1] - k1;
    const int* rowIndex = sn.s + sn.pi[t];
    const int rows = sn.pi[t + 1] - sn.pi[t];
    const double* block = lx + sn.px[t];
    for (int i = 0; i < rows; ++i) w[i] = y[rowIndex[i]];
    for (int j = columns - 1; j >= 0; --j) {
      const double* column = block + static_cast<long>(j) * rows;
      w[j] -= ConstVector(column + j + 1, rows - j - 1).dot(ConstVector(w + j + 1, rows - j - 1));
      if (!unit) w[j] /= column[j];
    }
    for (int j = 0; j < columns; ++j) y[k1 + j] = w[j];
  }
}



void SupernodalCholesky::solveLdlt(const cholmod_factor& L, const double* b, double* x) {
  const int* perm = static_cast<const int*>(L.Perm);
  double* y = permuted_.data();
  const auto n = static_cast<int>(L.n);
  for (int k = 0; k < n; ++k) y[k] = b[perm[k]];
  forwardSweep(L, y, true);
  backwardSweep(L, y, true);
  for (int k = 0; k < n; ++k) x[perm[k]] = y[k];
}

void SupernodalCholesky::solveUnitTransposed(const cholmod_factor& L, const double* u, double* x) {
  const int* perm = static_cast<const int*>(L.Perm);
  const auto n = static_cast<int>(L.n);
  double* y = permuted_.data();
  std::copy(u, u + n, y);
  backwardSweep(L, y, true);
  for (int k = 0; k < n; ++k) x[perm[k]] = y[k];
}

void SupernodalCholesky::pivots(const cholmod_factor& L, double* d) const {
  const double* lx = static_cast<const double*>(L.x);
  for (std::size_t k = 0; k < diagonal_.size(); ++k) d[k] = lx[diagonal_[k]];
}

}  // namespace jetshell
