#include "tools/scene/safeguard_report.h"

#include <algorithm>

namespace jetshell {

void SafeguardReport::add(const SolverSummary& s, bool accepted) {
  if (s.discarded) {
    ++discarded_;
  } else if (!s.converged()) {
    if (accepted) ++acceptedAtCap_;
    else ++cuts_[toString(s.reason)];
  }
  nonFiniteTrials_ += s.nonFiniteTrials;
  regularizations_ += s.regularizations;
  if (s.regularizations > 0) ++regularizedSolves_;
  for (const IterationRecord& r : s.trace) largestShift_ = std::max(largestShift_, r.shift);
  projectionFallbacks_ += s.projectionFallbacks;
  directFallbacks_ += s.directFallbacks;
}

nlohmann::json SafeguardReport::toJson(const std::string& iterationCapPolicy) const {
  int cuts = 0;
  for (const auto& [reason, n] : cuts_) cuts += n;
  return {{"step_cuts", cuts},
          {"step_cuts_by_reason", cuts_},
          {"non_finite_trials_rejected", nonFiniteTrials_},
          {"regularized_solves", regularizedSolves_},
          {"regularization_retries", regularizations_},
          {"largest_shift", largestShift_},
          {"projection_fallbacks", projectionFallbacks_},
          {"direct_factor_fallbacks", directFallbacks_},
          {"iteration_cap_outcome", iterationCapPolicy},
          {"steps_accepted_at_iteration_cap", acceptedAtCap_},
          {"steps_solved_again_from_previous_positions", discarded_}};
}

nlohmann::json SafeguardReport::state() const {
  return {{"cuts", cuts_},           {"non_finite_trials", nonFiniteTrials_}, {"regularized_solves", regularizedSolves_},
          {"regularizations", regularizations_}, {"projection_fallbacks", projectionFallbacks_},
          {"accepted_at_cap", acceptedAtCap_}, {"largest_shift", largestShift_}, {"solved_again", discarded_},
          {"direct_fallbacks", directFallbacks_}};
}

void SafeguardReport::restore(const nlohmann::json& j) {
  cuts_ = j.at("cuts").get<std::map<std::string, int>>();
  nonFiniteTrials_ = j.at("non_finite_trials").get<int>();
  regularizedSolves_ = j.at("regularized_solves").get<int>();
  regularizations_ = j.at("regularizations").get<int>();
  projectionFallbacks_ = j.at("projection_fallbacks").get<int>();
  acceptedAtCap_ = j.at("accepted_at_cap").get<int>();
  discarded_ = j.value("solved_again", 0);  // absent from checkpoints written before it was counted
  directFallbacks_ = j.value("direct_fallbacks", 0);  // likewise
  largestShift_ = j.at("largest_shift").get<double>();
}

}  // namespace jetshell
