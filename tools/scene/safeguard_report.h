// The solver safeguards that fired during a run, for summary.json ("safeguards"): every failed solve that cut
// its step (by reason: line_search_failure, non_finite, linear_solver_failure, iteration_cap, stalled, ...),
// line-search trial points rejected for a non-finite energy, indefinite systems regularized with a diagonal
// shift (count and largest shift), unprojected Hessians that fell back to the projected one, and steps accepted
// at the iteration cap (the scene's choice to move on instead of cutting: "iteration_cap_outcome"), and time
// steps solved again from their previous positions because the first solve ended above them (solvers/dynamics.h).
#pragma once

#include "solvers/solver_summary.h"

#include <nlohmann/json.hpp>

#include <map>
#include <string>

namespace jetshell {

class SafeguardReport {
 public:
  /// One Newton solve; `accepted`: its result was kept (a failed solve that was kept is a step at the cap).
  void add(const SolverSummary& solve, bool accepted);
  /// iterationCapPolicy: "move_on" (take the iterate) or "cut_step" (retry smaller, then stop).
  nlohmann::json toJson(const std::string& iterationCapPolicy) const;
  /// The counts for a checkpoint, and back.
  nlohmann::json state() const;
  void restore(const nlohmann::json& state);

 private:
  std::map<std::string, int> cuts_;
  int nonFiniteTrials_ = 0, regularizedSolves_ = 0, regularizations_ = 0, projectionFallbacks_ = 0;
  int directFallbacks_ = 0;  // PCG solves finished with the whole Hessian's factor (LinearSolverOptions::cgDirectAfter)
  int acceptedAtCap_ = 0, discarded_ = 0;
  double largestShift_ = 0.0;
};

}  // namespace jetshell
