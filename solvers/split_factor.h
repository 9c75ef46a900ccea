// The Cholesky factor of a symmetric matrix that is block diagonal over a partition of its vertices (3 dofs
// each): one CHOLMOD factor per part (solvers/cholmod_factor.h), the parts factored and solved side by side on
// the OpenMP threads. The one-ring preconditioner (solvers/one_ring_pattern.h) of a bisected mesh
// (solvers/vertex_bisection.h) is such a matrix: a factorization and a triangular solve of one part per core
// instead of one whole factor on one core, while the other waits.
// Inputs: the vertex partition (part[v] in 0 … parts−1; one part: the matrix is passed through untouched), the
// fill-reducing ordering; the matrix as its upper triangle (Eigen CSC, compressed), no entry coupling two parts.
// Outputs: as CholmodFactor: analysis (once per pattern), factorization of H + shift·I, solves; the statistics
// summed over the parts. Results do not depend on the thread count: each part's factor is computed alone.
#pragma once

#include "solvers/cholmod_factor.h"

#include <Eigen/Sparse>

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace jetshell {

class SplitFactor {
 public:
  using Status = CholmodFactor::Status;

  SplitFactor(FillOrdering ordering, int blasThreads);
  /// The partition of the vertices the next analysis uses (empty or all zero: one part).
  void setPartition(const std::vector<std::int8_t>& vertexPart);

  /// Symbolic analysis of each part of upper's pattern. Failed when an entry couples two parts.
  Status analyze(const Eigen::SparseMatrix<double>& upper);
  /// Numeric factorization of each part of upper + shift·I (the analysed pattern).
  Status factorize(const Eigen::SparseMatrix<double>& upper, double shift);
  /// x = (LLᵀ)⁻¹ b, part by part.
  Status solve(const Eigen::VectorXd& b, Eigen::VectorXd& x);

  bool analyzed() const { return analyzed_; }
  bool factorized() const { return factorized_; }
  int parts() const { return static_cast<int>(parts_.size()); }
  /// nnz(L) and flops summed over the parts; the first part's ordering.
  const FactorStatistics& statistics() const { return statistics_; }
  const std::string& message() const { return message_; }

 private:
  struct Part {
    std::unique_ptr<CholmodFactor> factor;
    std::vector<int> dofs;    // global dof of each local one, increasing
    std::vector<int> source;  // position in upper's values of each local entry
    Eigen::SparseMatrix<double> matrix;  // the part's upper triangle
    Eigen::VectorXd b, x;
    Status status = Status::Ok;
  };
  /// Runs f(part) for every part, side by side when there are threads to spare.
  template <typename F>
  void forEachPart(F&& f);
  Status collect(const char* what);

  FillOrdering ordering_;
  int blasThreads_;
  std::vector<std::int8_t> vertexPart_;
  std::vector<Part> parts_;
  bool analyzed_ = false, factorized_ = false;
  FactorStatistics statistics_;
  std::string message_;
};

}  // namespace jetshell
