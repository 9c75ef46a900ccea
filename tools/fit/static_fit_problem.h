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
// Inputs: an objective (finalized or not) and its load-carrying terms (LoadFactorHooks), a parameter mapping q (Q) → term parameter values
// with their Jacobian, observed coordinates. Outputs: FitEvaluation.
#pragma once

#include "solvers/sensitivity.h"
#include "solvers/statics.h"
#include "tools/fit/fit_problem.h"

#include <Eigen/Core>

#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace jetshell {

class StaticFitProblem : public FitProblem {
 public:
  /// levels: increasing load factors (> 0 unless the only level is 0: the unloaded state).
  /// Throws InputError for inconsistent inputs (dof or level out of range, negative weight, no observation).
  StaticFitProblem(Objective& objective, LoadFactorHooks loads, Eigen::VectorXd rest, ParameterMapping mapping,
                   std::vector<double> levels, std::vector<ObservedCoordinate> observed, LoadSteppingOptions options);
  ~StaticFitProblem();

  int numParameters() const override { return mapping_.numParameters; }
  const std::vector<double>& levels() const override { return levels_; }
  std::string levelName() const override { return "load factor"; }
  const std::vector<ObservedCoordinate>& observed() const override { return observed_; }
  const Eigen::VectorXd& rest() const override { return rest_; }

  /// Sets the parameters, solves every level and computes the residuals (and derivatives as asked). A failed
  /// solve or an equilibrium whose Hessian is not positive definite gives ok = false and a message.
  FitEvaluation evaluate(const Eigen::VectorXd& q, FitDerivatives derivatives) override;

 private:
  Objective& objective_;
  LoadFactorHooks loads_;
  Eigen::VectorXd rest_;
  ParameterMapping mapping_;
  std::vector<double> levels_;
  std::vector<ObservedCoordinate> observed_;
  LoadSteppingOptions options_;
  std::unique_ptr<EquilibriumSensitivity> sensitivity_;
};

}  // namespace jetshell
