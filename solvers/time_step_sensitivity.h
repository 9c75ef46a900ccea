// Forward sensitivities of an implicit time-stepping run (solvers/dynamics.h) to parameters of its terms.
//
// Every step minimizes an incremental potential Φ(x; x̃, y, p) whose inertia centre x̃ (the inertial predictor)
// and damping origin y depend on the state of earlier steps:
//   backward Euler:  x̃ = x_n + h v_n,                            y = x_n
//   BDF2:            x̃ = y + (8h/9)(v_n − v_{n−1}/4),            y = (4x_n − x_{n−1})/3
// At the step's minimizer ∇Φ(x_{n+1}) = 0 (free dofs), so with H the exact Hessian of Φ at x_{n+1}
//   S_{n+1} = dx_{n+1}/dp = −H⁻¹ (∂∇Φ/∂p + ∂∇Φ/∂x̃ · dx̃/dp + ∂∇Φ/∂y · dy/dp)
// where ∂∇Φ/∂p comes from the terms' parameter duals, ∂∇Φ/∂x̃ · X from the inertia term and ∂∇Φ/∂y · Y from
// the mass-damping term (both −c M X, exact for these quadratics) and the stiffness-damping terms (duals on their
// origins, core/origin_derivatives.h). Velocities follow the integrator's formulas, so their sensitivities are
// the same combinations: BE dv_{n+1}/dp = (S_{n+1} − S_n)/h; BDF2 (3S_{n+1} − 4S_n + S_{n−1})/(2h). P columns are
// carried forward (P ≤ 8), nothing of the trajectory is stored. Prescribed dofs have zero rows (their positions
// are functions of time only), and the run starts from a state that does not depend on p (S = 0).
//
// Exactness: S is the derivative of the computed trajectory when every step's Newton solve reached its
// minimizer; a solve accepted at the iteration cap (acceptIterationCap) is not one, and is counted
// (inexactSolves()), as is any solve whose final residual is above its tolerance and any solve the
// time-discretization rule ended (DynamicsOptions::updateTolerance > 0: Newton stops at a fraction of the step's
// truncation error, by design). The error of a converged
// solve is of the order of its residual tolerance.
//
// Inputs: a ShellSystem built for dynamics, the term parameters and d(term values)/dq (T × Q), the solver's
// accepted solves (SubstepView). Outputs: dx/dq, dv/dq (3N × Q) of the current state; counts.
#pragma once

#include "solvers/dynamics.h"
#include "solvers/sensitivity.h"
#include "solvers/shell_system.h"

#include <Eigen/Core>

#include <memory>
#include <string>
#include <vector>

namespace jetshell {

class TimeStepSensitivity {
 public:
  /// Throws InputError when the system has transient terms whose history dependence is not known here
  /// (contact damping and friction) or was not built for dynamics.
  explicit TimeStepSensitivity(ShellSystem& system);
  ~TimeStepSensitivity();
  TimeStepSensitivity(const TimeStepSensitivity&) = delete;
  TimeStepSensitivity& operator=(const TimeStepSensitivity&) = delete;

  /// Starts from a parameter-independent state (S = 0) for the term parameters and their Jacobian dv/dq
  /// (T × Q, Q ≤ 8); clears the counts of inexact solves (not the factorization counts).
  void reset(const std::vector<TermParameter>& parameters, const Eigen::MatrixXd& dvdq);

  /// Call before DynamicsSolver::step() ...
  void beginStep();
  /// ... and after it succeeded: the BDF2 history becomes the state at the step's start, as in the solver.
  void endStep();
  /// For the solver's substep observer: carries S over one accepted solve. Returns false (message()) when the
  /// Hessian at the solve's end is not positive definite or the factorization fails; S is then unchanged.
  bool advance(const SubstepView& view);

  const Eigen::MatrixXd& positions() const { return sx_; }   // dx/dq, 3N × Q
  const Eigen::MatrixXd& velocities() const { return sv_; }  // dv/dq
  /// Solves accepted unconverged (iteration cap, above their residual tolerance, or ended by the time-step rule)
  /// since reset().
  int inexactSolves() const { return inexact_; }
  int factorizations() const { return factor_.factorizations(); }
  int solves() const { return factor_.solves(); }
  const std::string& message() const { return message_; }

 private:
  ShellSystem& system_;
  EquilibriumSensitivity factor_;
  std::vector<TermParameter> parameters_;
  Eigen::MatrixXd dvdq_;
  Eigen::MatrixXd sx_, sv_, sxPrev_, svPrev_, sxStart_, svStart_;
  int inexact_ = 0;
  std::string message_;
};

}  // namespace jetshell
