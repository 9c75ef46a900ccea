// The solver safeguards that fired during a run, for summary.json ("safeguards"): every failed solve that cut
// its step (by reason: line_search_failure, non_finite, linear_solver_failure, iteration_cap, stalled, ...),
// line-search trial points rejected for a non-finite energy, indefinite systems regularized with a diagonal
// shift (count and largest shift), unprojected Hessians that fell back to the projected one, and steps accepted
// at the iteration cap (the scene's choice to move on instead of cutting: "iteration_cap_outcome"), and time
// steps solved again from their previous positions because the first solve ended above them (solvers/dynamics.h).
#pragma once

#include "solvers/solver_summary.h"
#include "tools/output/run_checkpoint.h"

#include <nlohmann/json.hpp>

#include <map>
#include <string>
#include <vector>

namespace jetshell {

class SafeguardReport {
 public:
  /// One Newton solve; `accepted`: its result was kept (a failed solve that was kept is a step at the cap).
  void add(const SolverSummary& solve, bool accepted);
  /// iterationCapPolicy: "move_on" (take the iterate) or "cut_step" (retry smaller, then stop).
  nlohmann::json toJson(const std::string& iterationCapPolicy) const;
  /// The counts for a checkpoint, and back (as runCheckpointFromJson checks them).
  const SafeguardCounts& state() const { return n_; }
  void restore(const SafeguardCounts& state);
  /// The names a step can be cut for (its solve's termination reason): the keys of the cuts by reason.
  static std::vector<std::string> cutReasons();

 private:
  // directFallbacks: PCG solves finished with the whole Hessian's factor (LinearSolverOptions::cgDirectAfter);
  // solvedAgain: time steps solved again from their previous positions.
  SafeguardCounts n_;
};

}  // namespace jetshell
