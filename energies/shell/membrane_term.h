// Membrane term: Σ_f scale · area_f · W_m(ε_f), ε = ½(a − A_origin), traces with the reference A⁻¹.
// Stages: x (9) -> e0, e1 (linear) -> a = [e_a·e_b] (MetricStage, constant Hessians) -> W_m(a)
// (MembraneDensityStage: Jets on the AD path, its analytic twin on the analytic path), one ComposedStage per face
// whose chain rule is the framework's (core/stage.h); the term adds only the translation-invariant completion
// over the face's vertices and the membrane's own projection of the edge block.
// setStaged(): the same energy as a stage graph (core/stage_graph.h): a = Metric(e0, e1) -> MembraneDensity(a)
// (energies/shell/shell_stages.h), chained by the framework, no derivative by hand.
#pragma once

#include "core/mesh.h"
#include "core/stage_graph.h"
#include "core/stage_graph_evaluator.h"
#include "energies/shell/shell_stages.h"
#include "energies/shell/reference_state.h"
#include "core/term.h"

#include <memory>
#include <string>
#include <vector>

namespace jetshell {

class MembraneTerm : public EnergyTerm {
 public:
  MembraneTerm(const TriMesh& mesh, const ShellReference& reference, double lambda, double mu);
  std::string name() const override { return name_; }
  StencilTable stencils() const override { return table_; }
  bool hasAnalytic() const override { return true; }
  /// Zero at the reference configuration until the origin is moved (stiffness damping: zero at x_prev).
  bool zeroAtRest() const override { return !originMoved_; }
  double evaluate(const Eigen::VectorXd& x, const EvalRequest& request, const EvalOptions& options) override;

  /// Parameters: "lambda", "mu" (λ, μ of W_m); a stiffness-damping term (makeStiffnessDamping) has "beta_R",
  /// "lambda", "mu" (its energy is β_R-scaled W_m with these moduli).
  /// Derivatives from duals seeded on them (core/parameter_derivatives.h).
  std::vector<std::string> parameterNames() const override;
  std::vector<double> parameterValues() const override;
  void setParameterValues(const std::vector<double>& values) override;
  void evaluateParameterDerivatives(const Eigen::VectorXd& x, ParameterDerivatives& out) override;

  /// Moves the strain origin to the metric of xOrigin and scales the energy: with scale = β_R/Δt and
  /// xOrigin = x_prev this is the stiffness-damping potential Δt·β_R·W_m(ε̇), ε̇ = (ε(x) − ε(x_prev))/Δt.
  void setStrainOrigin(const Eigen::VectorXd& xOrigin, double scale);
  void setName(std::string name) { name_ = std::move(name); }
  /// (∂²E/∂x∂y) S at x, y the strain origin last given to setStrainOrigin (zero before): how the gradient moves
  /// when the origin moves along the columns of S (3N × P, P ≤ 8). From duals (core/origin_derivatives.h).
  Eigen::MatrixXd originCrossDerivatives(const Eigen::VectorXd& x, const Eigen::MatrixXd& S) const;
  /// Makes this the stiffness-damping term: its parameter becomes β_R (value betaR > 0), and the energy
  /// scales with β_R / betaR relative to the scale given to setStrainOrigin.
  void makeStiffnessDamping(double betaR);

  /// Evaluates on the stage framework instead of one composed stage per face (same energy, to rounding).
  void setStaged(bool staged);
  bool staged() const { return staged_; }

 private:
  /// The membrane energy as a stage graph: per face the metric, then the density.
  using Graph = StageGraph<3, Local<MetricStage, Difference, Difference>, Local<MembraneDensityStage, From<0>>>;
  /// Points the density stage at this term's reference and current parameters (before each evaluation), and at
  /// the kept quadratics when `quadratic` (then up to date).
  void bindStages(bool quadratic = false);
  /// Brings quadratic_ up to date with λ, μ: each face's W_m'' (without the area scale) from Jets. The density is
  /// a quadratic in the metric, so a Hessian on the Jets takes it from here and only the value and gradient from
  /// first-order Jets (core/stage.h, per-entity quadratic); it does not depend on the strain origin.
  void updateQuadratics();
  std::vector<Eigen::Matrix3d> quadratic_;
  double quadraticLambda_ = 0.0, quadraticMu_ = 0.0;
  bool quadraticKept_ = false;
  bool staged_ = false;
  int numVertices_ = 0;
  std::unique_ptr<Graph> graph_;
  std::unique_ptr<StageGraphEvaluator<Graph>> graphEvaluator_;

  /// The face's energy over its edge vectors (e0, e1): the metric, then the density at the current parameters.
  using EnergyStage = ComposedStage<MetricStage, MembraneDensityStage>;
  EnergyStage energy_;
  /// One face; with a projection its block comes back projected (energies/shell/membrane_projection.h).
  double element(const Eigen::VectorXd& x, int f, const int* ids, bool wantG, bool wantH, DerivativePath path,
                 PsdProjection projection, Eigen::Matrix<double, 9, 1>& g, Eigen::Matrix<double, 9, 9>& H) const;

  std::string name_ = "membrane";
  StencilTable table_;
  ElementSchedule schedule_;
  ShellReference ref_;  // a copy: the term must not outlive borrowed data; metric = strain origin
  double lambda_, mu_;
  double scale_ = 1.0;
  double dampingReference_ = 0.0;  // > 0: a stiffness-damping term with parameter β_R (this value at scale_)
  double dampingValue_ = 0.0;
  double energyScale() const { return dampingReference_ > 0.0 ? scale_ * dampingValue_ / dampingReference_ : scale_; }
  bool originMoved_ = false;
  Eigen::VectorXd origin_;  // the positions the strain origin was taken from
  std::vector<double> elementEnergy_;
};

}  // namespace jetshell
