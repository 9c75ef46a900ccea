// The forward model of a dynamic fit: parameters q → term parameters → one implicit time-stepping run from the
// rest state (solvers/dynamics.h, the dynamic path of `jetshell run`) → the positions at the observed step times →
// weighted residuals, with derivatives by forward sensitivities through the steps (solvers/time_step_sensitivity.h):
// Q columns carried along the run, no stored trajectory. The Jacobian is the observed rows of dx/dq; the
// gradient is Jᵀr (forward, not adjoint: a discrete adjoint would store the trajectory and run backwards, which
// pays only for many parameters, and a fit has at most 8).
//
// Each step's loads are at the step's end time (λ(t), the scene's load ramp), as in `jetshell run`. The run stops
// at the last observed step. Derivatives are those of the computed trajectory when every Newton solve converged;
// a solve accepted at the iteration cap (DynamicsOptions::acceptIterationCap) makes them approximate, and the
// evaluation says so (FitEvaluation::derivativesExact, FitCounters::inexactDerivativeSolves).
//
// Inputs: the dynamic shell system, a parameter mapping, the dynamics options, λ(t), the observed steps (k ≥ 1,
// increasing) and coordinates. Outputs: FitEvaluation.
#pragma once

#include "solvers/dynamics.h"
#include "solvers/shell_system.h"
#include "solvers/time_step_sensitivity.h"
#include "tools/fit/fit_problem.h"

#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace jetshell {

class DynamicFitProblem : public FitProblem {
 public:
  /// steps: the observed step numbers (increasing, ≥ 1); observed coordinates' `level` index them. Throws
  /// InputError for inconsistent inputs (a system not built for dynamics, dof or level out of range, negative
  /// weight, no observation).
  DynamicFitProblem(ShellSystem& system, ParameterMapping mapping, DynamicsOptions options,
                    std::function<double(double)> loadFactorAtTime, std::vector<int> steps,
                    std::vector<ObservedCoordinate> observed);
  ~DynamicFitProblem();

  int numParameters() const override { return mapping_.numParameters; }
  const std::vector<double>& levels() const override { return times_; }
  std::string levelName() const override { return "time"; }
  const std::vector<ObservedCoordinate>& observed() const override { return observed_; }
  const Eigen::VectorXd& rest() const override { return rest_; }
  const std::vector<int>& steps() const { return steps_; }

  /// Sets the parameters, runs to the last observed step and computes the residuals (and derivatives as
  /// asked). A step that fails even after its cuts, or a step Hessian that is not positive definite when
  /// derivatives are asked for, gives ok = false and a message.
  FitEvaluation evaluate(const Eigen::VectorXd& q, FitDerivatives derivatives) override;

 private:
  ShellSystem& system_;
  ParameterMapping mapping_;
  DynamicsOptions options_;
  std::function<double(double)> loadFactorAtTime_;
  std::vector<int> steps_;
  std::vector<double> times_;
  std::vector<ObservedCoordinate> observed_;
  Eigen::VectorXd rest_;
  std::unique_ptr<TimeStepSensitivity> sensitivity_;  // built at the first evaluation with derivatives
};

}  // namespace jetshell
