// A CHOLMOD supernodal LLᵀ factor of a symmetric matrix given as its upper triangle (Eigen CSC), wrapped
// without copying (stype = 1). Used by the direct solver and by the lagged-factor preconditioner.
#pragma once

#include <Eigen/Sparse>

#include <memory>
#include <string>

namespace jetshell {

class CholmodFactor {
 public:
  enum class Status { Ok, NotPositiveDefinite, Failed };

  CholmodFactor();
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
  bool factorized() const { return factorized_; }
  /// What went wrong in the last failed call.
  const std::string& message() const { return message_; }

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  bool factorized_ = false;
  std::string message_;
};

}  // namespace jetshell
