// --newton-error of `jetshell bench dynamics` and `jetshell bench contact`: every step whose iterate test passed
// (solvers/dynamics.h), solved again from the same state, on from the accepted iterate, to a tight tolerance
// (solvers/step_error_check.h), and the distance between the two ends against the threshold the test promised,
// tallied by the estimate that passed it;
// a step taken in parts (cut, or divided for a moving solid) part by part. Solves accepted unconverged at the
// iteration cap are measured the same way, against their change.
// Inputs: each whole step's report and each part the run's substep observer sees, the run's solver, a second
// solver on its own system, the state the step started from. Outputs: per estimate, the passes checked (of them,
// parts), how many ended beyond their threshold, the worst ratio with its Newton iterations; the moved-on solves'
// worst error; and the solves that could not be checked (the tight solve did not converge, or the step was solved
// again from x_n).
#pragma once

#include "solvers/dynamics.h"
#include "solvers/shell_system.h"
#include "solvers/step_error_check.h"

#include <nlohmann/json.hpp>

#include <map>
#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace jetshell::cli {

struct EstimateCheck {
  int passes = 0;           // solves passed by this estimate and solved again
  int parts = 0;            // of them, parts of steps
  int aboveBound = 0;       // of them, error > threshold
  int partsAbove = 0;       // of those, parts of steps
  double worstRatio = 0.0;  // the largest error / threshold
  int worstStep = 0;
  std::string worstTrace;   // the worst pass's Newton iterations, and the tight solve's
};

/// Steps accepted at the iteration cap without convergence (DynamicsOptions::acceptIterationCap): no test
/// promised a bound, so the error is set against the step's change (‖x_tight − (x_n + Δt v_n)‖_M).
struct MovedOnCheck {
  int steps = 0;               // solves solved again and checked
  int parts = 0;               // of them, parts of steps
  double worstError = 0.0;     // [m]
  double worstRelative = 0.0;  // the largest error / change
  int worstStep = 0;           // the step of worstRelative
};

class NewtonErrorTally {
 public:
  /// Checks the step just taken (report `rep`, from `before`) against the same step taken by `tight`
  /// (tightStepOptions) on from the run's iterate, if an iterate test passed it or it moved on at the iteration cap.
  void check(const StepReport& rep, DynamicsSolver& run, DynamicsSolver& tight,
             const DynamicsSolver::Snapshot& before);
  /// Checks one part of step `step` (a solve over less than the run's Δt, from the run's substep observer) the
  /// same way (checkPartError); check() then leaves that step alone.
  void checkPart(const SubstepView& part, int step, DynamicsSolver& tight);
  bool empty() const { return checks_.empty() && unchecked_.empty() && movedOn_.steps == 0; }
  /// By estimate name ("residual estimate", "Newton correction").
  const std::vector<std::pair<std::string, EstimateCheck>>& checks() const { return checks_; }
  const MovedOnCheck& movedOn() const { return movedOn_; }
  /// Iterate-test passes (by estimate) and moved-on solves not checked: the tight solve did not converge, or the
  /// step was solved again from x_n.
  const std::map<std::string, int>& unchecked() const { return unchecked_; }
  nlohmann::json toJson() const;
  /// One line per estimate (and the worst pass's iterations), each starting with `indent`.
  void print(const char* indent) const;

 private:
  void record(const SolverSummary& loose, bool movedOn, int step, bool part, const StepErrorCheck& t);

  std::vector<std::pair<std::string, EstimateCheck>> checks_;
  MovedOnCheck movedOn_;
  std::map<std::string, int> unchecked_;
  std::string firstUnchecked_;  // why the first step not checked was not
};

/// --newton-error around one run: a tight solver (tightStepOptions) on a system of its own, so the checks leave the run
/// untouched, the state each step starts from, and the tally. Made before the run's first step, it hands each part of
/// a step taken in parts (a solve over less than the run's Δt) to the tally as the run takes it (the run's substep
/// observer, removed when the watch goes).
class NewtonErrorWatch {
 public:
  NewtonErrorWatch(DynamicsSolver& run, std::unique_ptr<ShellSystem> tightSystem);
  ~NewtonErrorWatch();
  NewtonErrorWatch(const NewtonErrorWatch&) = delete;
  NewtonErrorWatch& operator=(const NewtonErrorWatch&) = delete;
  /// After each of the run's steps (report `rep`): checks the step (NewtonErrorTally::check).
  void afterStep(const StepReport& rep);
  const NewtonErrorTally& tally() const { return tally_; }

 private:
  DynamicsSolver& run_;
  std::unique_ptr<ShellSystem> system_;  // before tight_, which refers to it
  DynamicsSolver tight_;
  DynamicsSolver::Snapshot before_;
  NewtonErrorTally tally_;
};

/// A solve's Newton iterations on one line: step length, largest move, which Hessian gave the direction
/// (unprojected near a solution, exact-first, or every block projected), and whether it was shifted.
std::string traceLine(const SolverSummary& s);

}  // namespace jetshell::cli
