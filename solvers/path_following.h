// The path-following loop of the statics path for arc-length and displacement control (solvers/path_control.h
// states the controls; solveStatics in solvers/statics.h dispatches here when options.path.control is not Load).
//
// Inputs: the objective, the load hooks, the start x (an equilibrium at startLoadFactor, or the rest state at 0),
// the stepping options. Outputs: the accepted equilibria (λ, x, the corrector's summary, the arc length or τ, the
// negative pivots of the tangent stiffness), the limit and bifurcation points, and the last equilibrium in x.
//
// Each step predicts (x, λ) and corrects it onto the path (solvers/path_corrector.h):
//  - predictor: the first step follows the start's tangent t = K⁻¹q; later steps extrapolate x and λ with the
//    polynomial through the last max(1, predictorOrder) + 1 path points in the path parameter (arc length or τ);
//  - arc length: the constraint radius is the predictor's distance from the last point, so the predictor lies on
//    it; a correction whose increment turns by more than 60° from the previous increment (or back along the
//    path), or changes λ by more than maxIncrement, is rejected and the step cut: a large step can jump to
//    another branch or cut a sharp turn short, and the start tangent that turns λ increments into arc lengths
//    can be far steeper than the path later (a branch leaving a bifurcation, solvers/branch_switching.h);
//  - jumps (with detectJumps): from the second step on, a step whose change of potential energy differs from the
//    loads' work along a continuous path of equilibria (solvers/path_energy.h) by more than LoadJump::kRatio of
//    that work landed on another branch. Arc length (tangentMismatch, dλ/dp from the tangent K⁻¹q at both ends)
//    cuts it, and keeps and reports (StaticsResult::loadJumps) only one the smallest increment cannot resolve.
//    Measured on a crumpled sheet under its weight (tests/solvers/path_following_test.cpp): with steps of up to
//    Δλ = 0.25 arc length reported turns at λ 0.068 and −0.101 without the check, and 0.1749 and −0.0504 with it
//    (400 short steps: 0.1739 and −0.0504). Displacement control (chordMismatch over the displacements) reports
//    its jumps without cutting: they are snap-backs, which no smaller step passes;
//  - arc length's largest increment: maxIncrement, lowered as the floor below where the path has stiffened (to
//    0.9 maxIncrement in λ along the last tangent), so that steps do not keep exceeding maxIncrement and being cut;
//  - a failed correction halves the increment (below minIncrement the run stops, keeping the last equilibrium;
//    arc length's increments are λ increments along the start's tangent, so where the path has stiffened since,
//    the floor is lowered to minIncrement in λ along the current tangent); after a step that took k iterations
//    the increment is scaled by √(easyIterations / k) within [½, growth];
//  - arc length's first increment moves no vertex by more than 5% of the shell's size along the start's tangent
//    (the arc length per λ unit is lowered to fit): a start as soft as a thin sheet under its weight (the linear
//    response to one level: kilometres) otherwise has every correction fail, however often it is cut;
//  - requested levels: displacement control lands on each τ level as load control does on λ; arc length lands on
//    every crossing of each λ level (and ends on the target) with a load-controlled correction started from the
//    chord between the two path points around it; a level whose correction fails cuts the step while the
//    increment can still be halved, and only then is reported in the message as missed.
//  - limit points: where λ rises then falls (or falls then rises) over three successive path points, the turn is
//    reported with its step and direction: the extremum of the cubic Hermite interpolant of λ(path parameter)
//    between the two of them whose tangents' dλ/dp differ in sign (hermiteTurn), else the vertex of the parabola
//    through the three.
//  - bifurcation points: where the count of negative pivots changes between two path points with no limit point at
//    either (solvers/path_control.h, BifurcationPoint);
//  - branch switching (arc length, LoadSteppingOptions::branchSwitching): a step from a stable point (no negative
//    pivot) to one with negative pivots, with dλ/dp of one sign at both ends (no limit point between), passed a
//    bifurcation. A step that also crosses a level is cut first; then load control's switch
//    (solvers/branch_switching.h) brackets the critical load, lands on the stable crossing branch, and the path
//    follows it from there (followNewBranch). A switch that fails is kept in branchSwitchFailure and the path goes
//    on along its own branch, reporting the bifurcation.
#pragma once

#include "solvers/statics.h"

namespace jetshell {

/// Follows the path with options.path.control (ArcLength or Displacement). Throws InputError for invalid options.
StaticsResult followPath(Objective& objective, const LoadFactorHooks& loads, Eigen::VectorXd& x,
                         const LoadSteppingOptions& options, const LoadStepCallback& callback);

/// After a branch switch (solvers/branch_switching.h) by load control or arc length: the landing as an accepted
/// step (its path parameter landingParameter), then the rest of the path by arc length from it to the target,
/// landing on the stops left after it; the tail's steps, limit, bifurcation and switch points and jumps are
/// renumbered after the steps so far and merged into `result` (an arc-length tail's path parameters continue from
/// the landing's). `increment` and `cuts` are the caller's at the switch. x is the path's last equilibrium on return.
void followNewBranch(Objective& objective, const LoadFactorHooks& loads, Eigen::VectorXd& x,
                     const LoadSteppingOptions& o, const LoadStepCallback& callback, const std::vector<double>& stops,
                     double increment, int cuts, BranchSwitchResult& sw, StaticsResult& result,
                     double landingParameter);

/// The abscissa of the vertex of the parabola through three points (p increasing) when it lies between the
/// outer two; otherwise (or for points on a line) the middle p.
double parabolaVertex(const double p[3], const double v[3]);

/// The turning point of λ(p) through three path points (p increasing): λ at parabolaVertex.
double limitLoadFactor(const double p[3], const double lambda[3]);

/// The turning point of λ(p) between two path points (pa < pb) whose slopes dλ/dp (ra, rb) have opposite signs:
/// the extremum of the cubic Hermite interpolant; `fallback` when it has none in [pa, pb] or is not finite.
double hermiteTurn(double pa, double la, double ra, double pb, double lb, double rb, double fallback);

}  // namespace jetshell
