#include "solvers/solver_summary.h"

#include <nlohmann/json.hpp>

#include <cstdio>
#include <sstream>

namespace jetshell {

const char* toString(TerminationReason r) {
  switch (r) {
    case TerminationReason::Converged: return "converged";
    case TerminationReason::IterationCap: return "iteration_cap";
    case TerminationReason::LineSearchFailure: return "line_search_failure";
    case TerminationReason::LinearSolverFailure: return "linear_solver_failure";
    case TerminationReason::NonFinite: return "non_finite";
    case TerminationReason::Stalled: return "stalled";
  }
  return "?";
}

std::string SolverSummary::briefReport() const {
  char buf[256];
  std::snprintf(buf, sizeof buf, "%s: %s after %d iterations, residual %.3e N (threshold %.3e), energy %.9e J, %.3f s",
                minimizer.c_str(), toString(reason), iterations, finalResidual, residualThreshold, finalEnergy,
                totalSeconds);
  return buf;
}

std::string SolverSummary::fullReport() const {
  std::ostringstream s;
  s << briefReport() << "\n";
  if (!message.empty()) s << "  " << message << "\n";
  s << "  iter        energy      residual     decrement   alpha   move [m]  ls  shift  H   assembly    factor     solve  "
       "linesearch\n";
  char buf[384];
  for (const IterationRecord& r : trace) {
    std::snprintf(buf, sizeof buf,
                  "  %4d  %12.6e  %12.4e  %12.4e  %6.3f  %9.3e  %2d  %5.0e  %c  %8.2fms  %6.2fms  %6.2fms  %8.2fms\n",
                  r.iteration, r.energy, r.residual, r.decrement, r.stepLength, r.largestMove, r.lineSearchEvaluations,
                  r.shift,
                  r.unprojected ? 'u' : r.exactHessian ? 'e' : (r.projectionFallback ? 'f' : 'p'),
                  1e3 * r.assemblySeconds, 1e3 * r.factorizationSeconds, 1e3 * r.solveSeconds,
                  1e3 * r.lineSearchSeconds);
    s << buf;
  }
  std::snprintf(buf, sizeof buf,
                "  time: assembly %.1f ms, factorization %.1f ms, solve %.1f ms, line search %.1f ms, total %.1f ms; "
                "%d symbolic analyses, %d regularizations, %d exact-Hessian steps (%d unprojected), "
                "%d projection fallbacks (%d unprojected)\n",
                1e3 * assemblySeconds, 1e3 * factorizationSeconds, 1e3 * solveSeconds, 1e3 * lineSearchSeconds,
                1e3 * totalSeconds, symbolicAnalyses, regularizations, exactHessianSteps, unprojectedSteps,
                projectionFallbacks, unprojectedFallbacks);
  s << buf;
  return s.str();
}

nlohmann::json toJson(const SolverSummary& m, bool withTrace) {
  nlohmann::json j = {{"minimizer", m.minimizer},
                      {"linear_solver", m.linearSolver},
                      {"termination", toString(m.reason)},
                      {"message", m.message},
                      {"iterations", m.iterations},
                      {"initial_energy", m.initialEnergy},
                      {"final_energy", m.finalEnergy},
                      {"discarded", m.discarded},
                      {"initial_residual", m.initialResidual},
                      {"final_residual", m.finalResidual},
                      {"final_decrement", m.finalDecrement},
                      {"residual_tolerance", m.residualThreshold},
                      {"force_scale", m.forceScale},
                      {"force_scale_source", m.forceScaleSource},
                      {"round_off_floor", m.roundOffFloor},
                      {"convergence_test", m.convergenceTest},
                      {"decrement_threshold", m.decrementThreshold},
                      {"assembly_seconds", m.assemblySeconds},
                      {"factorization_seconds", m.factorizationSeconds},
                      {"solve_seconds", m.solveSeconds},
                      {"line_search_seconds", m.lineSearchSeconds},
                      {"total_seconds", m.totalSeconds},
                      {"symbolic_analyses", m.symbolicAnalyses},
                      {"numeric_factorizations", m.numericFactorizations},
                      {"regularizations", m.regularizations},
                      {"exact_hessian_steps", m.exactHessianSteps},
                      {"projection_fallbacks", m.projectionFallbacks},
                      {"unprojected_steps", m.unprojectedSteps},
                      {"unprojected_fallbacks", m.unprojectedFallbacks},
                      {"direct_factor_fallbacks", m.directFallbacks},
                      {"non_finite_trials", m.nonFiniteTrials},
                      {"energy_evaluations", m.energyEvaluations},
                      {"gradient_evaluations", m.gradientEvaluations},
                      {"hessian_evaluations", m.hessianEvaluations}};
  if (withTrace) {
    nlohmann::json t = nlohmann::json::array();
    for (const IterationRecord& r : m.trace) {
      t.push_back({{"iteration", r.iteration},
                   {"energy", r.energy},
                   {"residual", r.residual},
                   {"decrement", r.decrement},
                   {"step_length", r.stepLength},
                   {"largest_move", r.largestMove},
                   {"line_search_evaluations", r.lineSearchEvaluations},
                   {"regularizations", r.regularizations},
                   {"shift", r.shift},
                   {"cg_iterations", r.cgIterations},
                   {"numeric_factorizations", r.numericFactorizations},
                   {"exact_hessian", r.exactHessian},
                   {"unprojected", r.unprojected},
                   {"projection_fallback", r.projectionFallback},
                   {"direct_factor_fallbacks", r.directFallbacks},
                   {"assembly_seconds", r.assemblySeconds},
                   {"factorization_seconds", r.factorizationSeconds},
                   {"solve_seconds", r.solveSeconds},
                   {"line_search_seconds", r.lineSearchSeconds}});
    }
    j["trace"] = t;
  }
  return j;
}

}  // namespace jetshell
