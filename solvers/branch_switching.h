// Branch switching for load control (solvers/statics.h) and arc length (solvers/path_following.h): a symmetric
// problem loaded past a bifurcation (a straight column or a flat plate in compression) keeps to its fundamental
// branch, which turns unstable there, and Newton cannot leave it for the stable branch far past the critical load
// (the buckled minimum lies metres away along a curved path). Here the crossing branch is reached where it leaves
// the fundamental one, as path-following codes do.
//
// Inputs: the objective and load hooks, a bracket on the fundamental branch, (λa, xa) a stable equilibrium and
// (λb, xb) one with negative eigenvalues, Newton's options, and the switch's options. Steps:
//  1. The critical load, bracketed by bisection on λ: Newton at the midpoint from the chord between the bracket's
//     equilibria (which keeps to the fundamental branch), then the midpoint's negative eigenvalues counted
//     (LDLᵀ pivots, solvers/stability_check.h). `bisections` halvings of the bracket.
//  2. The critical mode: inverse iteration with the LDLᵀ factor at the bracket's unstable end, started from its
//     direction of negative curvature. Near the critical load that is the softest eigenvector, the buckling mode.
//  3. The switch: from the bracket's unstable end (the anchor), a step along the mode whose largest vertex move is
//     `step` × the mean edge length, corrected onto the path by arc length (the bordered system on an LDLᵀ factor,
//     solvers/path_corrector.h) on the cylinder ‖Δu‖ = that step. The fundamental branch meets that cylinder only
//     far away (its dofs move little with λ), so the correction lands on the crossing branch.
//  4. The landing is accepted when the correction converged, the equilibrium there is stable (no negative
//     eigenvalue: a supercritical bifurcation) and its λ lies in (λa, λb] (or [λb, λa) where λ falls), not more
//     than four bracket widths below the bracket on the critical load (the branch starts there). Otherwise the
//     other sign of the mode is tried (an asymmetric bifurcation rises on one side only), then a step half as
//     long, four times.
// Output: the new branch's equilibrium (λ, x) and the bracket. Load control follows the new branch on by arc
// length: near a pitchfork its x grows as √(λ − λc), which no polynomial predictor in λ follows.
#pragma once

#include "solvers/indefinite_factor.h"
#include "solvers/newton.h"

#include <Eigen/Core>

#include <string>

namespace jetshell {

struct LoadFactorHooks;

struct BranchSwitchOptions {
  int bisections = 10;  // halvings of the bracket on the critical load (0..60)
  double step = 1.0;    // the switch's largest vertex move, in mean edge lengths (0, 100]
};

struct BranchSwitchResult {
  bool switched = false;
  double stableLoadFactor = 0.0;    // the bracket on the critical load after bisection: stable below ...
  double unstableLoadFactor = 0.0;  // ... unstable above
  int negativeEigenvalues = 0;      // at the bracket's unstable end
  double loadFactor = 0.0;          // the landing on the new branch (switched only)
  Eigen::VectorXd x;                // its equilibrium (switched only)
  SolverSummary summary;            // the correction that reached it (switched only)
  int newtonIterations = 0;         // all solves and corrections, including those not kept
  int factorizations = 0;           // LDLᵀ factorizations of the exact Hessian for stability counts
  std::string message;              // why no switch was made
};

/// Throws InputError naming the field (branchSwitch.bisections, branchSwitch.step) when an option is out of range.
void checkBranchSwitchOptions(const BranchSwitchOptions& options);

/// A switch that was not made, for StaticsResult::branchSwitchFailure: "between lambda = a and b: why".
std::string switchFailure(const BranchSwitchResult& r);

/// Why a landing at λ is not kept, given the step (λa, λb] and the bracket [stable, unstable] on the critical
/// load (step 4 above; λ may fall from λa to λb): "outside the step", "below the bracket on the critical load"
/// (more than four bracket widths), or empty.
std::string landingOutside(double lambda, double lambdaA, double lambdaB, double stable, double unstable);

/// The switch from the unstable fundamental branch at (λb, xb) to the stable branch crossing it between λa and λb.
/// `factor` is the caller's LDLᵀ factor (its symbolic analysis kept across calls). Leaves the load hooks at λb
/// when no switch was made, at the landing's λ otherwise.
/// `newton` solves the bisection's equilibria; its options (derivatives, tolerances, cap) serve the correction too.
BranchSwitchResult switchBranch(NewtonSolver& newton, const LoadFactorHooks& loads, IndefiniteFactor& factor,
                                const BranchSwitchOptions& options, double lambdaA, const Eigen::VectorXd& xa,
                                double lambdaB, const Eigen::VectorXd& xb);

}  // namespace jetshell
