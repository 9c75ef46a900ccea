// The forward model of a static fit: parameters q → term parameters → equilibria at the observed load levels →
// weighted residuals, with exact derivatives.
//
//   residual i:  r_i = √w_i (x*_{ℓ(i)}[dof_i] − target_i),   misfit f = ½ Σ r_i²
//   gradient:    adjoint, one linear solve per observed level (solvers/adjoint.h)
//   Jacobian:    forward sensitivities, Q solves per observed level (Gauss–Newton / Levenberg–Marquardt)
// Each evaluation solves from the rest state along one load path, the statics path of `jetshell run`
// (solveStatics, solvers/statics.h: adaptive increments, polynomial predictor, landing on every observed level;
// an observed level 0 is one solve at λ = 0 first). The cost is counted (load paths, Newton iterations and
// factorizations, sensitivity factorizations and solves): deterministic figures for the benchmark.
//
// Inputs: an objective (finalized or not) and its load term, a parameter mapping q (Q) → term parameter values
// with their Jacobian, observed coordinates. Outputs: FitEvaluation.
#pragma once

#include "solvers/sensitivity.h"
#include "solvers/statics.h"

#include <Eigen/Core>

#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace jetshell {

/// From fit parameters q (Q) to the values of the term parameters they set (T), and dvalues/dq (T × Q).
struct ParameterMapping {
  int numParameters = 0;  // Q
  std::vector<TermParameter> termParameters;
  std::function<void(const Eigen::VectorXd& q, Eigen::VectorXd& values, Eigen::MatrixXd* jacobian)> map;
};

/// One observed coordinate: x*[dof] at observed level `level` (an index into the problem's levels) should be
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
  std::vector<Eigen::VectorXd> equilibria;  // per level
};

/// Deterministic cost counts, accumulated over evaluations.
struct FitCounters {
  int evaluations = 0;            // forward evaluations (each solves every level)
  int fullSolves = 0;             // load paths from the rest state (one per evaluation; two with level 0)
  int newtonIterations = 0;
  int newtonFactorizations = 0;   // numeric Cholesky factorizations inside Newton
  int sensitivityFactorizations = 0;  // exact-Hessian factorizations for derivatives
  int sensitivitySolves = 0;          // triangular solves with them (adjoint: 1 per level, forward: Q per level)
  int gradientEvaluations = 0, jacobianEvaluations = 0;
};

class StaticFitProblem {
 public:
  /// levels: increasing load factors (> 0 unless the only level is 0: gravity or prescribed positions alone).
  /// Throws InputError for inconsistent inputs (dof or level out of range, negative weight, no observation).
  StaticFitProblem(Objective& objective, NodalForceTerm* loads, Eigen::VectorXd rest, ParameterMapping mapping,
                   std::vector<double> levels, std::vector<ObservedCoordinate> observed, LoadSteppingOptions options);
  ~StaticFitProblem();

  int numParameters() const { return mapping_.numParameters; }
  int numResiduals() const { return static_cast<int>(observed_.size()); }
  const std::vector<double>& levels() const { return levels_; }
  const std::vector<ObservedCoordinate>& observed() const { return observed_; }
  const Eigen::VectorXd& rest() const { return rest_; }

  /// Sets the parameters, solves every level and computes the residuals (and derivatives as asked). A failed
  /// solve or an equilibrium whose Hessian is not positive definite gives ok = false and a message.
  FitEvaluation evaluate(const Eigen::VectorXd& q, FitDerivatives derivatives);
  const FitCounters& counters() const { return counters_; }
  void resetCounters() { counters_ = FitCounters{}; }

 private:
  Objective& objective_;
  NodalForceTerm* loads_;
  Eigen::VectorXd rest_;
  ParameterMapping mapping_;
  std::vector<double> levels_;
  std::vector<ObservedCoordinate> observed_;
  LoadSteppingOptions options_;
  std::unique_ptr<EquilibriumSensitivity> sensitivity_;
  FitCounters counters_;
};

}  // namespace jetshell
