// How a static path is followed (solvers/statics.h): the control that decides each increment, and what the path
// reports where the load factor turns.
//
//  - Load: λ is prescribed level by level (Newton minimizes the energy at each λ). It cannot pass a limit point.
//  - ArcLength: λ is an unknown; each increment keeps the distance from the last equilibrium,
//    ‖Δu‖² + ψ² Δλ² ‖q‖² = Δs² (Crisfield's cylindrical arc length for ψ = 0, spherical for ψ = 1; u the free
//    dofs, q = −∂g/∂λ the load vector), so the path passes limit points where λ decreases (snap-through).
//    The path stops when λ reaches the target; it lands on every crossing of a requested level.
//  - Displacement: one dof's displacement from the start is prescribed, τ × `displacement` with τ running
//    0 → 1 over the levels; λ is the unknown that balances it. It passes load limit points, not snap-backs.
// Both non-load controls solve, per Newton iteration, the bordered system [K −q; cᵀ] with two solves on one
// LDLᵀ factor of K (solvers/path_corrector.h), which stays valid where K is indefinite.
#pragma once

#include <nlohmann/json_fwd.hpp>

#include <string>

namespace jetshell {

enum class PathControl { Load, ArcLength, Displacement };
const char* toString(PathControl c);  // "load", "arcLength", "displacement"

struct PathFollowingOptions {
  PathControl control = PathControl::Load;
  int maxSteps = 1000;        // accepted path points (arc length, displacement) before the run gives up
  double loadScaling = 0.0;   // ψ (arc length): 0 cylindrical, 1 spherical
  int controlledDof = -1;     // displacement: 3 × vertex + component (a free dof)
  double displacement = 0.0;  // displacement: the controlled dof's displacement at τ = 1 [m] (non-zero)
};

/// A turning point of the load factor along the path (between three successive path points).
struct LimitPoint {
  int step = 0;              // the accepted step (LoadStepResult::step) nearest the turn
  double loadFactor = 0.0;   // λ at the turn: the extremum of the cubic Hermite λ(path parameter) between the two
                             // path points whose tangents' dλ/dp differ in sign, else the vertex of the parabola
                             // through the three path points around the turn
  bool maximum = true;       // true: λ rose and turns down (a snap-through starts); false: it turns back up
};

/// A bifurcation passed by arc-length or displacement control: the count of negative eigenvalues of the tangent
/// stiffness changed between two successive path points with no limit point at either, so another branch crosses
/// the path there (a straight column's buckled one, say). The path keeps to the branch it was on, now unstable
/// if the count rose.
struct BifurcationPoint {
  int step = 0;                 // the accepted step after the change (LoadStepResult::step)
  double loadFactorBefore = 0.0, loadFactorAfter = 0.0;  // λ at the two path points
  int negativeBefore = 0, negativeAfter = 0;             // negative eigenvalues there
};

/// A load step whose two equilibria no continuous path joins: the step's change of potential energy differs from
/// the integral of ∂E/∂λ along a continuous path of equilibria (on which dE = ∂E/∂λ dλ, as ∂E/∂x = 0; a trapezoid,
/// third order in the step; solvers/path_energy.h) by more than kRatio of the loads' work in the step.
/// Load control: one half of the step keeps most of that (kConcentration); a snap-through past a limit point, which
/// load control passes as a jump to another branch, or a sheet so flexible that it swings from flat to hanging
/// within the step. Arc length cuts such a step, and reports only one that the smallest increment could not
/// resolve; displacement control reports its jumps (snap-backs, where the driven displacement turns back).
/// The equilibrium changed abruptly, and the path in between is not traced.
struct LoadJump {
  /// Measured on the static examples: smooth steps reach at most 0.014 (next to the hinged roof's limit point) at
  /// their scenes' load steps, and 0.078 with the whole load in one level (the pinched hemisphere's first step);
  /// the roof's snap-through under load control gives 2.9. (The cloth sheets of `jetshell stress` that swing
  /// under their weight give 0.7–0.97 in the first load step, which is not checked: solvers/statics.cpp.)
  static constexpr double kRatio = 0.25;
  /// A suspected jump is confirmed when one half of the step (split at an equilibrium solved at its midpoint) keeps
  /// more than this fraction of the released energy (solvers/statics.cpp).
  static constexpr double kConcentration = 0.75;
  int step = 0;                   // the accepted step that landed after the jump (LoadStepResult::step)
  double loadFactorBefore = 0.0, loadFactorAfter = 0.0;
  double energyReleased = 0.0;    // the trapezoid's energy change minus the step's (J; > 0 for a snap-through)
  double ratio = 0.0;             // |that| / the loads' work in the step
};

/// A jump as summary.json (`load_jumps`) and the validation's traces record it; load_step counts from 1.
nlohmann::json toJson(const LoadJump& jump);

/// A bifurcation that load control found on its path and left for the stable branch crossing it
/// (LoadSteppingOptions::branchSwitching, solvers/branch_switching.h).
struct BranchSwitchPoint {
  int step = 0;                   // the accepted step that landed on the new branch (LoadStepResult::step)
  double stableLoadFactor = 0.0;  // the bracket on the critical load: the fundamental branch is stable below ...
  double unstableLoadFactor = 0.0;  // ... and has negativeEigenvalues negative eigenvalues above
  int negativeEigenvalues = 0;
  double loadFactor = 0.0;        // λ where the path landed on the new branch
};

}  // namespace jetshell
