// A CHOLMOD supernodal LLᵀ factor of a symmetric matrix given as its upper triangle (Eigen CSC), wrapped
// without copying (stype = 1). Used by the direct solver and by the lagged-factor preconditioner; its LDLᵀ
// (factorizeLdlt) by path following's indefinite factor (solvers/indefinite_factor.h). CHOLMOD
// orders and analyses; the numeric factorization and the solves are solvers/supernodal_cholesky.h's, on
// CHOLMOD's analysis and in CHOLMOD's factor object.
// Inputs: the fill-reducing ordering (FillOrdering; Auto is CHOLMOD's default: AMD, then METIS when AMD's
// fill is poor), the matrix. Outputs: the factor, its solves, and the analysis statistics (nnz(L) and the
// flop count of one numeric factorization, deterministic for a given pattern and ordering).
// Threads: analyses and factorizations run with `blasThreads` OpenMP threads (default 1), restored afterwards
// (solves call no BLAS); with 0, the caller's OpenMP settings are left as they are (solvers/split_factor.h runs
// its parts on its own threads).
// OpenBLAS's OpenMP build (scripts/install-deps.sh) follows omp_get_max_threads() per call; other BLAS builds
// ignore it. Measured on the 2-core machine under load: the one-ring factor of the 2.6k-vertex cloth took
// 12–15 ms with one thread and 59–78 ms with two (small supernodes: the threads mostly wait at BLAS barriers).
#pragma once

#include "solvers/fill_ordering.h"

#include <Eigen/Sparse>

#include <memory>
#include <string>

struct cholmod_factor_struct;

namespace jetshell {

class CholmodFactor {
 public:
  enum class Status { Ok, NotPositiveDefinite, Failed };

  explicit CholmodFactor(FillOrdering ordering = FillOrdering::Auto, int blasThreads = 1);
  ~CholmodFactor();
  CholmodFactor(const CholmodFactor&) = delete;
  CholmodFactor& operator=(const CholmodFactor&) = delete;

  /// Symbolic analysis (fill-reducing ordering, supernodes) of upper's pattern.
  Status analyze(const Eigen::SparseMatrix<double>& upper);
  /// Numeric factorization of upper + shift·I (same pattern as analyzed).
  Status factorize(const Eigen::SparseMatrix<double>& upper, double shift);
  /// x = (LLᵀ)⁻¹ b with the current factor (x = (LDLᵀ)⁻¹ b after factorizeLdlt).
  Status solve(const Eigen::VectorXd& b, Eigen::VectorXd& x);
  /// Numeric LDLᵀ factorization without pivoting (unit L, pivots D) of upper, which may be indefinite (same
  /// pattern as analyzed): Failed on a zero or non-finite pivot, never NotPositiveDefinite.
  Status factorizeLdlt(const Eigen::SparseMatrix<double>& upper);
  /// D of the current LDLᵀ factor, in the factor's order (empty after an LLᵀ).
  const Eigen::VectorXd& pivots() const { return pivots_; }
  /// x = Pᵀ L⁻ᵀ u with the current LDLᵀ factor: u in the factor's order (as pivots()), x in the matrix's.
  Status solveUnitTransposed(const Eigen::VectorXd& u, Eigen::VectorXd& x);

  bool analyzed() const;
  /// nnz(L), flops and ordering of the last analysis (zeros before the first).
  const FactorStatistics& statistics() const { return statistics_; }
  bool factorized() const { return factorized_; }
  /// What went wrong in the last failed call.
  const std::string& message() const { return message_; }

 private:
  struct Impl;
  /// The analysed factor, made real, for a numeric factorization of upper; nullptr (with message_) if it cannot
  /// be: not analysed, or not upper's pattern.
  cholmod_factor_struct* numericFactor(const Eigen::SparseMatrix<double>& upper);

  std::unique_ptr<Impl> impl_;
  bool factorized_ = false;
  bool ldlt_ = false;  // the current factor is an LDLᵀ
  Eigen::VectorXd pivots_;
  FactorStatistics statistics_;
  int blasThreads_ = 1;
  std::string message_;
};

}  // namespace jetshell
