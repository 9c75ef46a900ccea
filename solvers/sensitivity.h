// Sensitivities of a static equilibrium to the energy terms' parameters (implicit-function theorem).
//
// At an equilibrium x*(p) the free part of the gradient vanishes, g(x*, p) = 0, so
//     H dx*/dp = −∂g/∂p           (H = ∂g/∂x, the exact Hessian at x*; ∂g/∂p = ∂²E/∂x∂p)
// with prescribed dofs held (their rows are identity in H and zero in ∂g/∂p). ∂²E/∂x∂p comes from the terms'
// evaluateParameterDerivatives (dual numbers seeded on the parameters); H from the objective's assembly with
// no PSD projection.
//
// Which factorization: the Newton solver's last factor belongs to the iterate before x* (and is the clamped,
// projected Hessian unless the last step was an exact-Hessian one), so it is not H(x*): using it would give
// gradients with an error of the order of the last step. EquilibriumSensitivity therefore assembles the exact
// H at x* once and factors it (CHOLMOD; the symbolic analysis is kept for every later equilibrium on the same
// pattern), then answers any number of right-hand sides with that factor: one triangular solve for an adjoint
// gradient (solvers/adjoint.h), P for the forward sensitivities of P parameters.
//
// Inputs: an objective, a configuration x (3N) that is an equilibrium, a list of (term, parameter) names.
// Outputs: ∂g/∂p (3N × P), solutions of H y = b (3N), counts of factorizations and solves.
#pragma once

#include "solvers/objective.h"

#include <Eigen/Core>

#include <memory>
#include <string>
#include <vector>

namespace jetshell {

class CholmodFactor;

/// One differentiable parameter of one active term, by name ("membrane", "lambda").
struct TermParameter {
  std::string term;
  std::string name;
};

class EquilibriumSensitivity {
 public:
  explicit EquilibriumSensitivity(Objective& objective);
  ~EquilibriumSensitivity();
  EquilibriumSensitivity(const EquilibriumSensitivity&) = delete;
  EquilibriumSensitivity& operator=(const EquilibriumSensitivity&) = delete;

  /// Assembles the exact (unprojected) Hessian at x and factors it. Returns false when it is not positive
  /// definite on the free dofs (an unstable or critical equilibrium: x*(p) is then not differentiable, or not
  /// unique) or the factorization fails; message() says which.
  bool factor(const Eigen::VectorXd& x);
  /// y = H⁻¹ b with the current factor; b's fixed entries are ignored and y's are zero. Requires factor().
  Eigen::VectorXd solve(const Eigen::VectorXd& b);

  /// ∂g/∂p at x: one column per parameter (3N × P), rows of fixed dofs zeroed. Throws InputError naming a
  /// term that is not active or a parameter it does not have.
  Eigen::MatrixXd mixedDerivatives(const Eigen::VectorXd& x, const std::vector<TermParameter>& parameters) const;

  /// Numeric factorizations and triangular solves done so far (deterministic cost measures).
  int factorizations() const { return factorizations_; }
  int solves() const { return solves_; }
  const std::string& message() const { return message_; }

 private:
  Objective& objective_;
  std::unique_ptr<CholmodFactor> factor_;
  std::uint64_t analyzedVersion_ = 0;
  bool analyzed_ = false;
  bool factored_ = false;
  int factorizations_ = 0;
  int solves_ = 0;
  std::string message_;
};

/// The value of a term parameter, and setting it (the other parameters of the term keep their values).
/// Throw InputError naming a term that is not active or a parameter it does not have.
double termParameterValue(const Objective& objective, const TermParameter& p);
void setTermParameterValue(Objective& objective, const TermParameter& p, double value);

}  // namespace jetshell
