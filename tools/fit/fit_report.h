// What a fit writes: fit.json (atomically) with the fitted values, their Gauss–Newton uncertainty, the
// termination reason, the cost counters and the history of every evaluation; and PNG plots (tools/render/plot.h): the
// misfit history and the fitted against the observed displacements (plus load–displacement curves when an
// observation spans several load levels).
//
// Inputs: the problem (levels, observed coordinates, rest state), the result, labels of the observation groups.
// Outputs: the JSON document, files in a directory.
#pragma once

#include "tools/fit/fit_optimizer.h"

#include <nlohmann/json.hpp>

#include <string>
#include <vector>

namespace jetshell {

struct FitReportInputs {
  const FitProblem* problem = nullptr;
  const FitResult* result = nullptr;
  std::vector<std::string> groupLabels;  // one per observation group
  std::string fitFile;                   // recorded, may be empty
  std::string description;
};

/// fit.json's content. Non-finite values (an evaluation that failed) are written as null.
nlohmann::json fitReportJson(const FitReportInputs& in);

/// Writes fit.json and, when `plots`, misfit_history.png, fit_vs_observed.png and (for multi-level observations)
/// curves.png into `directory` (created). Returns the files written; remarks on what was not written go to
/// `notes`.
std::vector<std::string> writeFitReport(const FitReportInputs& in, const std::string& directory, bool plots,
                                        std::vector<std::string>& notes);

/// A short human-readable summary (several lines) for the terminal.
std::string fitSummaryText(const FitReportInputs& in);

}  // namespace jetshell
