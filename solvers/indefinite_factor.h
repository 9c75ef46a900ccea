// A sparse LDLᵀ factor of a symmetric matrix that may be indefinite, with its inertia: the linear solve of
// path following (solvers/path_following.h), where the tangent stiffness between two limit points has a
// negative eigenvalue and the Cholesky solvers (solvers/linear_solver.h) would shift it away.
//
// Inputs: the matrix's upper triangle (compressed CSC, the HessianAssembler's matrix) and its pattern version.
// Outputs: the factor (analysed once per pattern version by CHOLMOD, its fill-reducing ordering; the numeric
// factorization is solvers/supernodal_cholesky.h's supernodal LDLᵀ without pivoting, BLAS updates per supernode),
// solves with it, and the number of negative pivots, which by Sylvester's law of inertia is the number of
// negative eigenvalues (fixed dofs are identity rows, so they count none): 0 on a stable equilibrium, 1 on the
// unstable branch of a snap-through. A zero or non-finite pivot is a failure, never a solution. Also used by load
// control (solvers/statics.h) to leave an unstable equilibrium along a direction of negative curvature.
#pragma once

#include "solvers/cholmod_factor.h"

#include <Eigen/Core>
#include <Eigen/SparseCore>

#include <cstdint>
#include <string>

namespace jetshell {

class IndefiniteFactor {
 public:
  /// Factors upper (its symmetric matrix); false on a zero or non-finite pivot (message() says which).
  bool factorize(const Eigen::SparseMatrix<double>& upper, std::uint64_t patternVersion);
  /// x = A⁻¹ b with the last successful factor; false when the result is not finite.
  bool solve(const Eigen::VectorXd& b, Eigen::VectorXd& x);
  /// A pivot counts as negative below −kRoundOffPivot × the largest |pivot|. Smaller ones, of either sign, are
  /// the round-off of a singular direction, not an eigenvalue: measured on a free, unloaded 3×3-vertex actor
  /// (6 rigid motions), 1e-15 of the largest and less; a strip in compression just past its buckling load (L/h
  /// 100) has a negative pivot of 1e-3 of the largest and its softest positive one 3e-6. The softest pivots fall
  /// about as (h / L)² with a shell's slenderness (estimated, not measured: near 1e-7 at a garment's L/h of 500),
  /// still far above this bound.
  static constexpr double kRoundOffPivot = 1e-10;
  /// Negative pivots of the last successful factor: the count of the matrix's negative eigenvalues.
  int negativePivots() const { return negative_; }
  /// A direction of negative curvature of the last successful factor's matrix A: with P A Pᵀ = L D Lᵀ and u the
  /// sum of the unit vectors e_i of its negative pivots, d = Pᵀ L⁻ᵀ u, so that dᵀ A d = Σ D_ii < 0 (every negative
  /// direction at once: a saddle that is symmetric in several independent ways is left in one step). False when
  /// there is none (no negative pivot) or d is not finite.
  bool negativeCurvatureDirection(Eigen::VectorXd& d);
  /// The symbolic analyses done (one per pattern version).
  int analyses() const { return analyses_; }
  const std::string& message() const { return message_; }

 private:
  CholmodFactor ldlt_;
  bool factorized_ = false;
  bool empty_ = false;  // the last matrix was 0 × 0
  std::uint64_t version_ = 0;
  bool analyzed_ = false;
  int analyses_ = 0;
  int negative_ = 0;
  double negativeBelow_ = 0.0;  // pivots below this count as negative
  std::string message_;
};

}  // namespace jetshell
