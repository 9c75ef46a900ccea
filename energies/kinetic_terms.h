// Diagonal quadratic terms of an incremental potential: inertia and mass damping.
//
// Both have the form ½ c Σ_v m_v |x_v − y_v|² with lumped vertex masses m_v, a coefficient c and a centre y
// that the time integrator moves before every step:
//   inertia       c = 1/Δt² (backward Euler) or 9/(4Δt²) (BDF2), y = the inertial predictor x̃;
//   mass damping  c = α_R/Δt (backward Euler) or 3α_R/(2Δt) (BDF2), y = x_prev (BE) or (4x_n − x_{n−1})/3 (BDF2),
// so that ∇ = c M (x − y) is M ẍ-like or α_R M ẋ with the integrator's velocity. The Hessian is c·m_v·I per
// vertex (one 1-vertex stencil per vertex).
//
// Each has one differentiable parameter q that scales the energy relative to the value q₀ it was built with:
// E = ½ c (q/q₀) Σ_v m_v |x_v − y_v|², with c as given to setCentre (which is understood at q₀). Inertia: q =
// "density" (q₀ = the density the masses were lumped with); mass damping: q = "alpha_R" (q₀ = the α_R the
// integrator's coefficient was computed with).
#pragma once

#include "core/term.h"

#include <Eigen/Core>

#include <string>
#include <vector>

namespace jetshell {

class DiagonalQuadraticTerm : public EnergyTerm {
 public:
  /// name: the term's name in an objective ("inertia", "mass_damping"). vertexMass: m_v (size N, >= 0).
  /// parameter: the name of q and its reference value q₀ (> 0). Starts with c = 0 and y = 0: call setCentre
  /// before use.
  DiagonalQuadraticTerm(std::string name, Eigen::VectorXd vertexMass, std::string parameter = "scale",
                        double parameterValue = 1.0);

  std::string name() const override { return name_; }
  StencilTable stencils() const override { return table_; }
  bool hasAnalytic() const override { return true; }
  bool zeroAtRest() const override { return false; }
  bool rigidInvariant() const override { return false; }
  /// ½ c Σ m_v |x_v − y_v|²; adds c m_v (x_v − y_v) and c m_v I (one block per vertex). Projection is moot
  /// (the blocks are PSD for c >= 0).
  double evaluate(const Eigen::VectorXd& x, const EvalRequest& request, const EvalOptions& options) override;

  std::vector<std::string> parameterNames() const override { return {parameter_}; }
  std::vector<double> parameterValues() const override { return {parameterValue_}; }
  void setParameterValues(const std::vector<double>& values) override;
  void evaluateParameterDerivatives(const Eigen::VectorXd& x, ParameterDerivatives& out) override;

  /// (∂²E/∂x∂y) S = −c (q/q₀) M S: how the gradient moves when the centre y moves along the columns of S
  /// (3N × P). The energy is quadratic in x − y, so this is exact (tested against differences of gradients).
  Eigen::MatrixXd centreCrossDerivatives(const Eigen::MatrixXd& S) const;
  /// Sets the centre y (size 3N) and the coefficient c (>= 0).
  void setCentre(const Eigen::VectorXd& centre, double coefficient);
  const Eigen::VectorXd& centre() const { return centre_; }
  double coefficient() const { return coefficient_; }
  const Eigen::VectorXd& vertexMass() const { return mass_; }

 private:
  std::string name_;
  Eigen::VectorXd mass_;
  Eigen::VectorXd centre_;
  double coefficient_ = 0.0;
  std::string parameter_;
  double parameterReference_, parameterValue_;
  StencilTable table_;
  /// c·q/q₀: the coefficient of the energy.
  double effectiveCoefficient() const { return coefficient_ * parameterValue_ / parameterReference_; }
};

/// Inertia ½ c Σ m_v |x_v − x̃_v|² ("inertia"); parameter "density", the masses being given at `density`.
std::shared_ptr<DiagonalQuadraticTerm> makeInertiaTerm(const Eigen::VectorXd& vertexMass, double density = 1.0);
/// Mass damping ½ c Σ m_v |x_v − y_v|² with c ∝ α_R ("mass_damping"); parameter "alpha_R", c being given at
/// α_R = alphaR.
std::shared_ptr<DiagonalQuadraticTerm> makeMassDampingTerm(const Eigen::VectorXd& vertexMass, double alphaR = 1.0);

}  // namespace jetshell
