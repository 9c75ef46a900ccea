// NLopt's L-BFGS (NLOPT_LD_LBFGS) on an Objective's free dofs: the gradient-only alternative minimizer, for
// comparison with Newton on static problems.
//
// It stops on the same residual test as Newton (‖g_free‖∞ ≤ residualTolerance × force scale, see newton.h),
// checked at every evaluation (NLopt is then force-stopped), or when NLopt gives up. NLopt does not report
// iterations: SolverSummary::iterations counts objective evaluations.
#pragma once

#include "core/term.h"
#include "solvers/objective.h"
#include "solvers/solver_summary.h"

#include <Eigen/Core>

namespace jetshell {

struct LbfgsOptions {
  int maxEvaluations = 20000;
  int memory = 10;  // stored correction pairs
  double residualTolerance = 1e-6;
  DerivativePath derivatives = DerivativePath::Analytic;
};

/// Minimizes from x (size 3N, in/out; prescribed dofs keep their values). x ends at the best finite point seen.
SolverSummary minimizeLbfgs(Objective& objective, Eigen::VectorXd& x, const LbfgsOptions& options = {});

}  // namespace jetshell
