// A CHOLMOD supernodal LLᵀ factor of a symmetric matrix given as its upper triangle (Eigen CSC), wrapped
// without copying (stype = 1). Used by the direct solver and by the lagged-factor preconditioner.
// Inputs: the fill-reducing ordering (FillOrdering; Auto is CHOLMOD's default: AMD, then METIS when AMD's
// fill is poor), the matrix. Outputs: the factor, its solves, and the analysis statistics (nnz(L) and the
// flop count of one numeric factorization, deterministic for a given pattern and ordering).
#pragma once

#include "solvers/fill_ordering.h"

#include <Eigen/Sparse>

#include <memory>
#include <string>

namespace jetshell {

class CholmodFactor {
 public:
  enum class Status { Ok, NotPositiveDefinite, Failed };

  explicit CholmodFactor(FillOrdering ordering = FillOrdering::Auto);
  ~CholmodFactor();
  CholmodFactor(const CholmodFactor&) = delete;
  CholmodFactor& operator=(const CholmodFactor&) = delete;

  /// Symbolic analysis (fill-reducing ordering, supernodes) of upper's pattern.
  Status analyze(const Eigen::SparseMatrix<double>& upper);
  /// Numeric factorization of upper + shift·I (same pattern as analyzed).
  Status factorize(const Eigen::SparseMatrix<double>& upper, double shift);
  /// x = (LLᵀ)⁻¹ b with the current factor.
  Status solve(const Eigen::VectorXd& b, Eigen::VectorXd& x);

  bool analyzed() const;
  /// nnz(L), flops and ordering of the last analysis (zeros before the first).
  const FactorStatistics& statistics() const { return statistics_; }
  bool factorized() const { return factorized_; }
  /// What went wrong in the last failed call.
  const std::string& message() const { return message_; }

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  bool factorized_ = false;
  FactorStatistics statistics_;
  std::string message_;
};

}  // namespace jetshell
