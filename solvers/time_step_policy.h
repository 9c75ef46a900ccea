// Named Newton policies for implicit time steps.
// Inputs: a policy name. Output: the DynamicsOptions fields that the policy fixes (Newton tests, line search,
// start, what to do at the iteration cap); integrator and Δt are left as they are.
//  - page:      the engine the spec comes from: at most 4 Newton iterations, absolute residual tolerance 1e-3 N,
//               relative 1e-6, the residual-norm line search, and "move on" (accept the unconverged iterate)
//               when the cap is hit; each such step is counted as moved on, never as converged.
//  - jetshell:  the time-discretization stopping rule (solvers/dynamics.h): stop once a Newton error estimate
//               (the residual's, or the last full Newton correction's) is below η = jetshellUpdateTolerance of
//               ‖x − x̃‖ (the step's local-truncation-error scale), or at the static residual test; Armijo line
//               search; start from the extrapolated trajectory (the integrator's own constant-acceleration step); a step that
//               does not converge in 20 iterations is cut (halved), never accepted unconverged. With the
//               linear solver on auto: CG preconditioned by the one-ring factor, stopped at Eisenstat–Walker
//               forcing terms (NewtonOptions::adaptiveLinearTolerance).
//  - reference: tight static convergence (residual 1e-10 × force scale, up to 200 iterations), for reference
//               trajectories.
#pragma once

#include "solvers/dynamics.h"

#include <string>

namespace jetshell {

enum class TimeStepPolicy { Page, Jetshell, Reference };

TimeStepPolicy timeStepPolicyFromString(const std::string& name);  // page | jetshell | reference
const char* toString(TimeStepPolicy p);

/// η of the jetshell policy (chosen by `jetshell bench dynamics`, see BENCHMARKS.md "Dynamics").
constexpr double jetshellUpdateTolerance = 0.1;

/// The linear algebra of time steps, for every policy and for scenes: a linear solver left on auto becomes CG
/// preconditioned by the one-ring factor with Eisenstat–Walker forcing terms, and a projected Hessian is tried
/// unprojected first (NewtonOptions::exactHessianFirst). Fields set explicitly are kept.
void applyTimeStepLinearAlgebra(NewtonOptions& newton);

/// Sets the fields of `options` that the policy fixes.
void applyTimeStepPolicy(TimeStepPolicy policy, DynamicsOptions& options);

}  // namespace jetshell
