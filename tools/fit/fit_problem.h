// The forward model a fit minimizes over, whatever the analysis: parameters q → term parameters → the states at
// the observed levels (load factors of a static path, or times of a dynamic run) → weighted residuals, with
// exact derivatives. StaticFitProblem (tools/fit/static_fit_problem.h) and DynamicFitProblem
// (tools/fit/dynamic_fit_problem.h) implement it; the optimizers (tools/fit/fit_optimizer.h) and the report
// (tools/fit/fit_report.h) see only this.
//
//   residual i:  r_i = √w_i (x_{ℓ(i)}[dof_i] − target_i),   misfit f = ½ Σ r_i²
//
// Inputs: parameter values q (Q) and which derivatives to compute. Outputs: FitEvaluation, cost counters.
#pragma once

#include "solvers/sensitivity.h"

#include <Eigen/Core>

#include <functional>
#include <string>
#include <vector>

namespace jetshell {

/// From fit parameters q (Q) to the values of the term parameters they set (T), and dvalues/dq (T × Q).
struct ParameterMapping {
  int numParameters = 0;  // Q
  std::vector<TermParameter> termParameters;
  std::function<void(const Eigen::VectorXd& q, Eigen::VectorXd& values, Eigen::MatrixXd* jacobian)> map;
};

/// One observed coordinate: x[dof] at observed level `level` (an index into the problem's levels) should be
/// `target`, with weight ≥ 0. `group` ties it to the observation it came from (reports).
struct ObservedCoordinate {
  int level = 0;
  int dof = 0;
  double target = 0.0;
  double weight = 1.0;
  int group = 0;
};

enum class FitDerivatives { None, Gradient, Jacobian };

struct FitEvaluation {
  bool ok = false;
  std::string message;         // why not
  double misfit = 0.0;         // ½ Σ r²
  Eigen::VectorXd residuals;   // M
  Eigen::VectorXd gradient;    // Q, with FitDerivatives::Gradient (or Jacobian: Jᵀr)
  Eigen::MatrixXd jacobian;    // M × Q, with FitDerivatives::Jacobian
  std::vector<Eigen::VectorXd> equilibria;  // per level: the equilibrium (static) or the state at that time
  /// False when the derivatives are not those of the computed states: some solve they pass through stopped
  /// short of its minimizer (a dynamic step accepted at the iteration cap).
  bool derivativesExact = true;
};

/// Deterministic cost counts, accumulated over evaluations.
struct FitCounters {
  int evaluations = 0;            // forward evaluations (each solves every level)
  int fullSolves = 0;             // load paths or dynamic runs from the rest state
  int timeSteps = 0;              // time steps (dynamic runs)
  int newtonIterations = 0;
  int newtonFactorizations = 0;   // numeric Cholesky factorizations inside Newton
  int sensitivityFactorizations = 0;  // exact-Hessian factorizations for derivatives
  int sensitivitySolves = 0;          // triangular solves with them
  int gradientEvaluations = 0, jacobianEvaluations = 0;
  /// Solves accepted short of convergence on the way to derivatives (iteration cap): their evaluations' derivatives
  /// are approximate.
  int inexactDerivativeSolves = 0;
};

class FitProblem {
 public:
  virtual ~FitProblem() = default;
  virtual int numParameters() const = 0;
  int numResiduals() const { return static_cast<int>(observed().size()); }
  /// The observed levels, increasing: load factors (static) or times in s (dynamic).
  virtual const std::vector<double>& levels() const = 0;
  /// "load factor" or "time" (reports).
  virtual std::string levelName() const = 0;
  virtual const std::vector<ObservedCoordinate>& observed() const = 0;
  virtual const Eigen::VectorXd& rest() const = 0;
  /// Sets the parameters, solves every level and computes the residuals (and derivatives as asked). A failed
  /// solve gives ok = false and a message.
  virtual FitEvaluation evaluate(const Eigen::VectorXd& q, FitDerivatives derivatives) = 0;
  const FitCounters& counters() const { return counters_; }
  void resetCounters() { counters_ = FitCounters{}; }

 protected:
  /// Throws InputError for coordinates whose level or dof is out of range, or with a negative or non-finite
  /// weight or target, or none at all.
  static void checkObserved(const std::vector<ObservedCoordinate>& observed, int numLevels, int numDofs);
  /// The start of an evaluation: checks q (else out.message, false), counts it, maps q to the term parameters
  /// (with dv/dq into dvdq when derivatives are asked for) and sets them on the objective.
  bool applyParameters(Objective& objective, const ParameterMapping& mapping, const Eigen::VectorXd& q,
                       FitDerivatives derivatives, FitEvaluation& out, Eigen::MatrixXd& dvdq);
  /// out.residuals and out.misfit from out.equilibria; false (out.message) for a non-finite misfit.
  bool computeResiduals(FitEvaluation& out) const;

  FitCounters counters_;
};

}  // namespace jetshell
