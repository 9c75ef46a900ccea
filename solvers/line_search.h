// Line searches along a descent direction d: φ(α) = E(x + αd), φ'(α) = ∇E(x + αd)·d.
//
//  - None: α = 1, accepted whatever φ does (only a non-finite value fails).
//  - BacktrackingArmijo: from α = 1, accept when φ(α) ≤ φ(0) + c1 α φ'(0); otherwise the minimizer of the
//    quadratic through φ(0), φ'(0), φ(α), kept within [0.1α, 0.5α] (0.5α after a non-finite value).
//  - ResidualNorm: from α = 1, accept when ‖∇E(x + αd)‖₂ ≤ (1 − c1 α) ‖∇E(x)‖₂; otherwise halve α. A projected
//    Hessian does not make d a descent direction for ‖∇E‖ (measured: on a cantilever plate it stalled at
//    α ≈ 1e-4 for 200 iterations), so once α < 1/16 the largest tried α that passed the Armijo energy test
//    is taken instead.
//  - StrongWolfe: Nocedal & Wright, Algorithms 3.5 and 3.6 (bracketing from α = 1, growing ×2 up to α = 4, then
//    zoom by safeguarded cubic interpolation): φ(α) ≤ φ(0) + c1 α φ'(0) and |φ'(α)| ≤ c2 |φ'(0)|.
// Energy comparisons allow `energyNoise` (the round-off of the summed energy), so that a step that is exact to
// machine precision is not rejected for a change below the noise.
#pragma once

#include <functional>
#include <string>

namespace jetshell {

enum class LineSearchType { None, BacktrackingArmijo, ResidualNorm, StrongWolfe };

LineSearchType lineSearchTypeFromString(const std::string& name);  // none | armijo | residual | wolfe
const char* toString(LineSearchType t);

/// A point of the search. slope and residual are only meaningful when hasGradient.
struct LineSearchPoint {
  double alpha = 0.0;
  double energy = 0.0;
  double slope = 0.0;     // φ'(α)
  double residual = 0.0;  // ‖∇E‖₂ at x + αd (free dofs)
  bool hasGradient = false;
  bool finite = true;
};

/// Evaluates x + αd; computes slope and residual when wantGradient.
using LineSearchEvaluator = std::function<LineSearchPoint(double alpha, bool wantGradient)>;

struct LineSearchOptions {
  LineSearchType type = LineSearchType::BacktrackingArmijo;
  double c1 = 1e-4;
  double c2 = 0.9;
  int maxEvaluations = 30;
  double energyNoise = 0.0;
};

struct LineSearchResult {
  bool success = false;
  bool allNonFinite = false;  // every trial point had a non-finite energy or gradient
  LineSearchPoint point;      // the accepted point (success) or the last one tried
  int evaluations = 0;
  std::string message;
};

/// Searches from `start` (α = 0, with energy, slope and residual). start.slope must be negative.
LineSearchResult lineSearch(const LineSearchOptions& options, const LineSearchPoint& start,
                            const LineSearchEvaluator& evaluate);

}  // namespace jetshell
