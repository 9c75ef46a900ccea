// Static equilibrium along a load path: the one statics path of jetshell (`jetshell run` and `jetshell validate`).
//
// Inputs: an Objective, the load factor's targets (LoadFactorHooks: the nodal forces, the weight, and any other
// term whose load scales with λ, such as an end moment; the path starts from the unloaded rest state; prescribed
// positions are evaluated at "time" λ, so a prescribed motion ramps with the loads, and so are a moving solid's
// keyframes: movingSolids, below), the start x (3N), and the options. Output: every accepted equilibrium (λ, x,
// the Newton summary), flagged when it sits on a requested level.
//
// Load control: λ rises from startLoadFactor to targetLoadFactor and lands exactly on every requested level.
// Each Newton solve starts from the polynomial through the last order + 1 equilibria (order ≤ predictorOrder,
// adapted along the path), extrapolated to the new λ (rotation-free shells need it: Newton's linearization of a large rotation stretches the membrane,
// so without a good start each increment costs tens of iterations whatever its size; VALIDATION.md). A step
// that fails (iteration cap, line-search or linear-solver failure, non-finite values) is cut: x returns to the
// last equilibrium, the increment halves and it is retried; after each step the increment is scaled towards easyIterations
// Newton iterations per step. Load control cannot pass a limit point: the increments are cut down to minIncrement and
// the run stops there, keeping the last equilibrium. At a bifurcation (a stable step followed by a saddle) load
// control switches to the stable crossing branch and follows it by arc length (branchSwitching,
// solvers/branch_switching.h). Arc-length and displacement control (options.path, solvers/path_control.h; the loop
// in solvers/path_following.h) pass limit points and report them.
#pragma once

#include "energies/shell/shell_terms.h"
#include "solvers/branch_switching.h"
#include "solvers/path_control.h"
#include "solvers/newton.h"
#include "solvers/shell_system.h"
#include "solvers/solver_summary.h"

#include <Eigen/Core>

#include <functional>
#include <string>
#include <vector>

namespace jetshell {

/// The terms λ reaches besides the prescribed positions: every load-carrying term.
struct LoadFactorHooks {
  NodalForceTerm* nodalForces = nullptr;  // scaled by λ (may be null)
  GravityTerm* gravity = nullptr;         // the weight, scaled by λ (may be null)
  /// Other load-carrying terms: set(λ) before a solve, accept(x) after an equilibrium is accepted (terms
  /// with path state, such as the end moment's unwrapped angle). Either may be empty.
  struct Hook {
    std::function<void(double)> set;
    std::function<void(const Eigen::VectorXd&)> accept;
  };
  std::vector<Hook> others;
  /// How far the solids λ moves travel near the shell between two load factors [m] (solvers/statics.h:
  /// movingSolidTravel); empty: none moves. The force scale judges it as prescribed motion
  /// (Objective::setPrescribedPath).
  std::function<double(double from, double to)> solidMotion;

  void set(double lambda) const;
  void accept(const Eigen::VectorXd& x) const;
};

struct LoadSteppingOptions {
  double startLoadFactor = 0.0;   // the λ of the start x (an equilibrium there, or the rest state at 0)
  double targetLoadFactor = 1.0;
  std::vector<double> levels;     // λ values the path must land on (each reported with atLevel); the target is
                                  // always one. Need not be sorted; values outside (start, target] are rejected.
  double initialIncrement = 1.0;  // first Δλ (clipped to the next level)
  double minIncrement = 1e-4;     // give up below this Δλ
  double maxIncrement = 1.0;
  double growth = 1.5;            // largest factor between successive increments
  int easyIterations = 6;         // the Newton iterations an increment aims at: after a step that took k,
                                  // Δλ ×= √(easyIterations / k), clamped to [½, growth]
  int predictorOrder = 3;         // 0: start from the last equilibrium; k: the polynomial through k + 1 of them
                                  // (the largest order: it drops by one after a prediction that landed farther
                                  // from the new equilibrium than the last one, and climbs back when the next
                                  // order would have landed at least twice as close)
                                  // (Newton iterations over the validation set, orders 2 -> 3: slit plate 256 -> 187,
                                  // page ring 274 -> 208, end shear 93 -> 66, end moment 165 -> 151; VALIDATION.md)
  NewtonOptions newton;
  /// Unstable equilibria (load control). With checkStability, every step whose Newton solve did not end on an
  /// unshifted Cholesky factorization of the true Hessian (SolverSummary::lastHessianPositiveDefinite) is checked:
  /// the exact Hessian at its equilibrium is factored (LDLᵀ, solvers/indefinite_factor.h) and its negative
  /// eigenvalues counted (LoadStepResult::negativePivots). So are checked: steps that needed a shifted system (the
  /// tangent stiffness was indefinite on the way), steps that converged without factoring anything (a predictor
  /// that lands on the equilibrium, as on a flat column's straight path past its buckling load), and every step
  /// solved with a projected Hessian or an iterative linear solver, which cannot tell. Steps that end on a positive
  /// definite factor get no extra factorization. A saddle of the potential, such as a flat sheet in compression
  /// that a symmetric start never leaves (Newton's steps keep the symmetry to the bit), is left downhill: the
  /// equilibrium moves by saddleStep × the mean edge length along the negative pivots' direction of negative
  /// curvature and Newton solves again, up to saddleEscapes times (0: report only). A saddle that is not left (no
  /// escape allowed, or the new solve failed or did not lower the energy) is kept and counted
  /// (StaticsResult::unstableSteps).
  bool checkStability = true;
  int saddleEscapes = 3;
  double saddleStep = 0.1;
  /// Bifurcations (load control, with checkStability): when a step leaves an equilibrium known to be stable (a
  /// positive definite factor vouched for it, or its check found no negative eigenvalue) for a saddle, the
  /// critical load is bracketed by bisection and the path switches to the stable branch crossing there
  /// (solvers/branch_switching.h), then follows it by arc length to the target, landing on the levels left
  /// (StaticsResult::branchSwitches). A switch that finds no stable branch leaves the step to the saddle escapes
  /// above. Before the first step no equilibrium was accepted: when that step lands on a saddle, the start is solved
  /// at its λ and checked, and serves as the stable end. Arc length switches too, where its path goes from a stable
  /// point past a bifurcation (solvers/path_following.h).
  bool branchSwitching = true;
  BranchSwitchOptions branchSwitch;
  /// Load control: report the steps whose equilibrium changed abruptly (StaticsResult::loadJumps, LoadJump in
  /// solvers/path_control.h): a snap-through past a limit point, which load control passes as a jump to another
  /// branch, or a sheet that swings under a small load. Costs four energy evaluations a step, and a midpoint solve
  /// where a jump is suspected. Arc length: cuts a step that jumped to another branch (solvers/path_following.h),
  /// and reports one the smallest increment cannot resolve; displacement control reports its jumps (snap-backs).
  /// Four energy evaluations, two gradients and one solve on the corrector's factor per path point.
  bool detectJumps = true;
  /// The control (solvers/path_control.h). Load: the above as stated. ArcLength: levels and the target are
  /// load factors, landed on at every crossing, the path ends at the target; the increments are load-factor
  /// increments turned into arc lengths by the start's tangent. Displacement: levels and increments are
  /// fractions τ ∈ (0, 1] of path.displacement, the path ends at τ = 1 (targetLoadFactor is not used).
  PathFollowingOptions path;
};

struct LoadStepResult {
  int step = 0;             // accepted-step index, from 0
  double loadFactor = 0.0;  // λ reached
  bool atLevel = false;     // λ is one of the requested levels (or the target)
  Eigen::VectorXd x;        // the equilibrium (3N)
  SolverSummary summary;    // the Newton solve that reached it
  int cuts = 0;             // failed attempts before this step was accepted
  double pathParameter = 0.0;  // arc length from the start (ArcLength), τ (Displacement) or λ (Load)
  int negativePivots = -1;     // negative eigenvalues of the tangent stiffness there (path control, and load
                               // control's check of unstable equilibria; -1: not checked)
};

struct StaticsResult {
  bool completed = false;  // the target λ was reached
  bool stopped = false;    // the callback asked to stop
  double loadFactor = 0.0;
  std::vector<LoadStepResult> steps;
  int totalCuts = 0;
  int newtonIterations = 0;
  std::vector<SolverSummary> failedSolves;  // the attempts that were cut (without their traces)
  std::vector<std::string> activeTerms;
  std::vector<LimitPoint> limitPoints;  // where λ turned (arc-length and displacement control), in path order
  std::vector<BifurcationPoint> bifurcationPoints;  // the same controls, in path order
  std::vector<BranchSwitchPoint> branchSwitches;  // load control's switches to a stable branch, in path order
  std::vector<LoadJump> loadJumps;  // steps that jumped (load control's snap-throughs; path control's unresolved)
  std::string branchSwitchFailure;  // why a switch was tried and not made (empty: none failed)
  int saddleEscapes = 0;  // unstable equilibria left downhill (load control, LoadSteppingOptions::saddleEscapes)
  int unstableSteps = 0;  // accepted steps whose equilibrium was found unstable and kept so
  int stabilityChecks = 0;  // equilibria factored by checkStability (each one LDLᵀ, and one more per escape)
  std::string message;
};

/// Called after each accepted load step; return false to stop cleanly (the result keeps the steps so far).
using LoadStepCallback = std::function<bool(const LoadStepResult&)>;

/// Load stepping from x (3N, in/out: on return the last equilibrium; prescribed values are applied at each λ).
/// Throws InputError for invalid options.
StaticsResult solveStatics(Objective& objective, const LoadFactorHooks& loads, Eigen::VectorXd& x,
                           const LoadSteppingOptions& options, const LoadStepCallback& callback = {});
/// The load-carrying terms of a system (its nodal forces, its weight and its end moments; any may be absent),
/// plus `extra`.
LoadFactorHooks loadFactorHooks(ShellSystem& system, const std::vector<LoadFactorHooks::Hook>& extra = {});
/// The same on a ShellSystem built for AnalysisKind::Statics (its loadFactorHooks plus `extra` hooks), with the
/// options forMovingSolids.
StaticsResult solveStatics(ShellSystem& system, Eigen::VectorXd& x, const LoadSteppingOptions& options,
                           const LoadStepCallback& callback = {}, const std::vector<LoadFactorHooks::Hook>& extra = {});

/// The options of a path from x on a statics system with moving solids (movingSolids): the path must be
/// load-controlled (else InputError naming the solid: λ is the solid's time, which arc length and displacement
/// control solve for), branch switching is off (it corrects and continues by arc length), and the increments are
/// at most movingSolidIncrement. Unchanged without a moving solid.
LoadSteppingOptions forMovingSolids(const ShellSystem& system, const Eigen::VectorXd& x, LoadSteppingOptions o);

/// The volume actors of a statics system that move along the load path (their keyframes, read at time λ), each
/// named once.
std::vector<std::string> movingSolids(const ShellSystem& system);

/// The farthest any moving solid's material near the shell (at x) moves between load factors `from` and `to`
/// [m] (VolumeContactState::solidTravel); 0 when none moves.
double movingSolidTravel(const ShellSystem& system, const Eigen::VectorXd& x, double from, double to);

/// The most load increments a static path takes to follow a moving solid (movingSolidIncrement).
constexpr double kMaxMovingSolidIncrements = 1024.0;

/// The largest load-factor increment from `start` to `target` in which no moving solid moves near the shell (at x)
/// by more than ShellContact::stepFraction of its thinnest half-width (ShellContact::solidSweep over each stretch
/// between two keyframe times, in equal parts; the smallest part of any stretch): a Newton solve sees a solid only
/// where it is at the step's λ, so one that moves farther between two solves could pass through the shell unseen.
/// Infinity when none needs a bound. Throws InputError naming the solid and the stretch when the path would need
/// more than kMaxMovingSolidIncrements such increments, or when a solid has more keyframes than that on it.
double movingSolidIncrement(const ShellSystem& system, const Eigen::VectorXd& x, double start, double target);

/// The stops of a path in path order, ending with the target: the levels (validated: each must lie after
/// start and not beyond target), sorted, without repeats. Throws InputError naming the bad level.
std::vector<double> pathStops(double start, double target, const std::vector<double>& levels);

/// The start of a Newton solve at λ: the Lagrange polynomial through the newest `points` (λ, x) pairs of the
/// history (newest first; all of them when points < 0), extrapolated to λ; the newest x when there is only one.
Eigen::VectorXd extrapolateEquilibria(const std::vector<std::pair<double, Eigen::VectorXd>>& history, double lambda,
                                      int points = -1);

/// Newton's options for static paths: the per-element PSD projection off. On large-rotation paths the
/// projected Hessian makes Newton's convergence linear (the slit annular plate at 4 x 32 quads: 658 iterations
/// projected, 296 unprojected); indefinite systems are still handled by the linear solver's shift retries.
NewtonOptions staticNewtonOptions();

}  // namespace jetshell
