// The energy-term interface the objective sums and the derivative checker tests.
//
// A term knows its stencils, its parameters and its energy; evaluate() adds value, gradient and Hessian at a
// configuration. Terms built from one templated element energy derive from ElementEnergyTerm
// (energies/element_energy_term.h) and get all of this from the framework.
#pragma once

#include "core/assembly.h"
#include "core/psd_projection.h"
#include "core/stencil.h"

#include <Eigen/Core>

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace jetshell {

/// Which derivatives serve: forward-mode duals (Ceres Jet) or the hand-derived twin, where a term has one.
enum class DerivativePath { AutoDiff, Analytic };
/// The Hessian a term assembles: exact, or Gauss–Newton for a term that offers it, Jᵀ W'' J of its energy density
/// W over its inner quantities without their second derivatives (the bending term and staged terms: the root
/// stage's curvature alone, core/stage_graph.h). A term without a Gauss–Newton form stays exact.
enum class HessianModel { Exact, GaussNewton };
HessianModel hessianModelFromString(const std::string& name);  // exact | gaussNewton
/// Exact friction Hessian, or the majorizer's: along the slip the curvature of the regularized Coulomb
/// potential is replaced by its secant value f₁(y)/y (energies/contact/contact_ramp.h), with the same energy and
/// gradient.
enum class FrictionHessian { Exact, Majorizer };

struct EvalOptions {
  DerivativePath path = DerivativePath::Analytic;
  PsdProjection projection = PsdProjection::None;
  HessianModel hessianModel = HessianModel::Exact;
  /// With a projection: only element blocks of at most this many dofs are projected (0: every block). Read by
  /// the Objective, which evaluates the terms with wider stencils unprojected.
  int projectionMaxBlockDofs = 0;
  FrictionHessian frictionHessian = FrictionHessian::Exact;
};

/// What to compute. gradient and hessian may be null; the energy is always returned.
/// The gradient is added into *gradient (size 3N); Hessian blocks go into *hessian at hessianSlot.
struct EvalRequest {
  Eigen::VectorXd* gradient = nullptr;
  HessianAssembler* hessian = nullptr;
  int hessianSlot = -1;
};

/// Derivatives of a term's energy with respect to its differentiable parameters p (size P), at a configuration x
/// (size 3N). Both come from dual numbers seeded on the parameters, never from finite differences.
struct ParameterDerivatives {
  Eigen::VectorXd energy;  // ∂E/∂p, size P
  Eigen::MatrixXd mixed;   // ∂²E/∂x∂p = ∂g/∂p, 3N × P (rows ordered as x; prescribed dofs are not zeroed)
};

class EnergyTerm {
 public:
  virtual ~EnergyTerm() = default;
  /// Short name, unique within an objective ("membrane", "bending", "gravity", ...).
  virtual std::string name() const = 0;
  /// The vertices each element touches (declares the Hessian pattern). Empty width for Hessian-free terms.
  virtual StencilTable stencils() const = 0;
  /// True when a hand-derived gradient and Hessian exist (DerivativePath::Analytic).
  virtual bool hasAnalytic() const { return false; }
  /// Energy at x (size 3N); adds derivatives as requested.
  virtual double evaluate(const Eigen::VectorXd& x, const EvalRequest& request, const EvalOptions& options) = 0;
  /// True when the energy is zero (with zero gradient) at the reference configuration, for the conformance
  /// suite. Loads (gravity, nodal forces) are not.
  virtual bool zeroAtRest() const { return true; }
  /// True when the energy is invariant under rigid motions of the whole configuration.
  virtual bool rigidInvariant() const { return true; }

  // Terms whose elements follow the configuration (contact pairs from a broad phase). The objective calls
  // updateStencils(x) before every evaluation and rebuilds its Hessian pattern when stencilVersion() changed.
  // A term with fixed stencils keeps the defaults.
  /// Brings stencils() up to date for positions x.
  virtual void updateStencils(const Eigen::VectorXd& /*x*/) {}
  /// Changes whenever stencils() changed.
  virtual std::uint64_t stencilVersion() const { return 0; }
  /// True for such terms (their stencils, and so the Hessian's pattern, may change between evaluations).
  virtual bool stencilsFollowConfiguration() const { return false; }

  // Parameters as differentiable inputs (fitting, sensitivities). A term exposes the constants its energy is
  // a smooth function of (λ, μ, α, β, density, damping coefficients, load magnitudes, contact stiffness, ...)
  // under stable names; the default is a term with none.
  /// Names of the differentiable parameters, in a fixed order (empty: none).
  virtual std::vector<std::string> parameterNames() const { return {}; }
  /// Their current values, in parameterNames() order.
  virtual std::vector<double> parameterValues() const { return {}; }
  /// Replaces the values (same order and count; InputError otherwise). Later evaluations use them.
  virtual void setParameterValues(const std::vector<double>& values);
  /// ∂E/∂p and ∂²E/∂x∂p at x. The default throws InputError for a term with parameters that did not override it.
  virtual void evaluateParameterDerivatives(const Eigen::VectorXd& x, ParameterDerivatives& out);
};

using EnergyTermPtr = std::shared_ptr<EnergyTerm>;

}  // namespace jetshell
