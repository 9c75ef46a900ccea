#include "tools/scene/safeguard_report.h"

#include <algorithm>

namespace jetshell {

void SafeguardReport::add(const SolverSummary& s, bool accepted) {
  if (s.discarded) {
    ++n_.solvedAgain;
  } else if (!s.converged()) {
    if (accepted) ++n_.acceptedAtCap;
    else ++n_.cuts[toString(s.reason)];
  }
  n_.nonFiniteTrials += s.nonFiniteTrials;
  n_.regularizations += s.regularizations;
  if (s.regularizations > 0) ++n_.regularizedSolves;
  for (const IterationRecord& r : s.trace) n_.largestShift = std::max(n_.largestShift, r.shift);
  n_.projectionFallbacks += s.projectionFallbacks;
  n_.directFallbacks += s.directFallbacks;
}

nlohmann::json SafeguardReport::toJson(const std::string& iterationCapPolicy) const {
  int cuts = 0;
  for (const auto& [reason, n] : n_.cuts) cuts += n;
  return {{"step_cuts", cuts},
          {"step_cuts_by_reason", n_.cuts},
          {"non_finite_trials_rejected", n_.nonFiniteTrials},
          {"regularized_solves", n_.regularizedSolves},
          {"regularization_retries", n_.regularizations},
          {"largest_shift", n_.largestShift},
          {"projection_fallbacks", n_.projectionFallbacks},
          {"direct_factor_fallbacks", n_.directFallbacks},
          {"iteration_cap_outcome", iterationCapPolicy},
          {"steps_accepted_at_iteration_cap", n_.acceptedAtCap},
          {"steps_solved_again_from_previous_positions", n_.solvedAgain}};
}

std::vector<std::string> SafeguardReport::cutReasons() {
  // A solve that converged cuts nothing: every other termination reason may have.
  std::vector<std::string> names;
  for (TerminationReason r :
       {TerminationReason::IterationCap, TerminationReason::LineSearchFailure, TerminationReason::LinearSolverFailure,
        TerminationReason::NonFinite, TerminationReason::Stalled})
    names.emplace_back(toString(r));
  return names;
}

void SafeguardReport::restore(const SafeguardCounts& state) { n_ = state; }

}  // namespace jetshell
