// A time step's Newton error, measured: the step a run just took, solved again from the same state by a second
// solver on its own system to a tight tolerance, on from the run's accepted iterate, and the distance between
// the two ends. The time stepper's iterate test promises that a passed step ends within its threshold of the
// solution; this measures the promise (`jetshell bench dynamics --newton-error`,
// tests/solvers/dynamics_error_bound_test.cpp).
#pragma once

#include "solvers/dynamics.h"

#include <Eigen/Core>

namespace jetshell {

/// The mass-weighted RMS vertex length of u (3N) [m]: sqrt(Σ_v m_v |u_v|² / Σ_v m_v), as the time stepper's
/// error estimates measure it.
double massWeightedRms(const Eigen::VectorXd& mass, const Eigen::VectorXd& u);

struct StepErrorCheck {
  bool checked = false;  // false: the step taken (or part), or the tight one, was not one Newton solve over
                         // its whole Δt, or the tight solve did not converge
  double error = 0.0;    // ‖x_run − x_tight‖_M [m]
  double change = 0.0;   // ‖x_tight − (x_n + Δt v_n)‖_M [m]: the step's change against its predictor
  bool solvedAgain = false;  // the tight solver took the step (or part) again
  StepReport tight;          // its report
};

/// The tight solves' DynamicsOptions::updateTolerance.
constexpr double kTightUpdateTolerance = 1e-6;

/// The run's options made tight: η = kTightUpdateTolerance; no correction test with contact terms (its threshold
/// is at least δ/100 whatever η, so the tight solve would end where the run did); the direct solver on a fixed
/// linear tolerance, exact-first with no block projected first; at least 50 Newton iterations, and a solve at the
/// cap fails, uncut, instead of moving on (then nothing is checked).
DynamicsOptions tightStepOptions(const DynamicsOptions& run);

/// Checks the whole step `run` just took from `before` (its report `taken`): `tight`, a solver on its own system
/// with a tight DynamicsOptions::updateTolerance, is restored to `before` (BDF2's history with it) and takes the
/// same step, solved on from the run's accepted iterate to the solution near it, as a part is (checkPartError).
/// The run's Newton history and options do not matter. Until session 70 the tight solve started from x_n, so
/// that the two would follow the same iterates up to the pass; they did only where their options agreed, and
/// where they did not (tightStepOptions projects no block first and takes the direct solver) a step that is not
/// convex could end at another minimum: on a hanging cloth with BDF2 a Newton correction pass measured 17.2 times
/// its threshold that way and 0.304 times on from its iterate (BENCHMARKS.md, Dynamics, session 69). An iterate
/// beside a saddle has no solution near: the tight solve leaves it for a minimum, and the distance reported is to
/// that minimum.
StepErrorCheck checkStepError(const StepReport& taken, DynamicsSolver& run, DynamicsSolver& tight,
                              const DynamicsSolver::Snapshot& before);

/// Whether a step was taken in parts: cut, or divided up front for a moving solid. Its parts are checked one by
/// one (checkPartError); the step as a whole is not.
bool takenInParts(const StepReport& r);

/// Checks one part of a step taken in parts, as the run's substep observer sees it: `tight` is set to the part's
/// start (t_n, x_n, v_n; no BDF2 history, as parts are backward Euler) and Δt, takes it as one step solved on
/// from the part's accepted iterate, and is set back to its own Δt. A part's iterates cannot be followed from x_n
/// as a whole step's are (it may start from the step's extrapolated acceleration, and with the Newton history of
/// the step's earlier parts), so the tight solve starts where the run ended and goes on to the solution near it.
/// An iterate at a saddle (a flat sheet under in-plane compression) has none near: the tight solve leaves it for
/// a minimum, and the distance reported is to that minimum.
StepErrorCheck checkPartError(const SubstepView& part, DynamicsSolver& tight);

}  // namespace jetshell
