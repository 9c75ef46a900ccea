// The energy identity of a path of equilibria, which tells a step that followed the path from one that jumped
// to another branch (LoadJump, solvers/path_control.h).
//
// Along a continuous path of equilibria dE = ∂E/∂x · dx + ∂E/∂λ dλ = ∂E/∂λ dλ, since ∂E/∂x = 0 on the free dofs
// (∂E/∂λ moves the prescribed positions with λ). So a step's change of potential energy must match the integral of
// s = ∂E/∂λ over the step, to third order in the step by a trapezoid. The mismatch is measured against the loads'
// work in the step, from h = s − s at the path's start positions (the loads' work on the displacements, −q·u for
// dead loads; the energy of dead loads on absolute positions would drown the difference). Two trapezoids:
//  - chordMismatch: ½ (s_a + s_b) Δλ against ½ |Δλ| (|h_a| + |h_b|) (load control), or, by parts the trapezoid
//    of ∫ λ dh, against ½ |Δh| (|λ_a| + |λ_b|) (displacement control, whose λ(τ) is singular at a snap-back and
//    jumps there at nearly the same displacement).
//  - tangentMismatch: ∫ h dλ/dp dp by the trapezoid in the path parameter p, with dλ/dp from the tangent K⁻¹q at
//    both ends, and the rest of s (a function of λ alone) in λ; against ½ |Δp| (|h_a λ'_a| + |h_b λ'_b|), which does
//    not vanish where λ turns within the step (a limit point) as |Δλ| does. Arc length.
// Measured on the one-vertex snap-through of tests/solvers/path_following_test.cpp and on the thin hinged roof
// (`jetshell validate hinged-cylindrical-roof --thickness 6.35 ...`): near its snap-back, displacement control's
// tangent ratio reached 0.19 on smooth steps (dλ/dτ of −75 to −216) where the chord's was 2e-5; arc length's steps
// that jumped between the roof's close limit points near P = 0 read 0.2–2 by tangents and 0.001 by the chord.
//
// Inputs: the objective, the load hooks, an equilibrium (x, λ), the path's start positions, and dλ/dp there.
// Outputs: PathEnergy per equilibrium; PathMismatch between two (the energy a jump released, and the loads' work
// in the step that measures it).
#pragma once

#include "solvers/objective.h"

#include <Eigen/Core>

namespace jetshell {

struct LoadFactorHooks;

/// The potential energy and its partial derivative in λ at an equilibrium, and the same derivative at the path's
/// start positions.
struct PathEnergy {
  double lambda = 0.0, energy = 0.0, slope = 0.0, referenceSlope = 0.0;
  double loadRate = 1.0;  // dλ/dp there (tangentMismatch)
};

/// PathEnergy at the equilibrium x at λ (four energy evaluations; ∂E/∂λ by a forward difference with the
/// prescribed positions moving, so every load hook counts). Leaves the hooks at λ.
PathEnergy pathEnergy(Objective& objective, const LoadFactorHooks& loads, const Eigen::VectorXd& x, double lambda,
                      const Eigen::VectorXd& start, const EvalOptions& options, double loadRate = 1.0);

/// Between two equilibria on a path: the trapezoid's energy change minus the actual one (the energy released by a
/// jump; > 0 for a snap-through) and the loads' work on the displacements in between (> 0).
struct PathMismatch {
  double released = 0.0, work = 0.0;
};

/// The loads' work in a step, for chordMismatch: over the step's λ (load control), or over its displacements
/// (displacement control: at a snap-back λ jumps at nearly the same displacement, and ½ |Δλ| (|h_a| + |h_b|) would
/// count the jump itself as work).
enum class ChordWork { OverLoadFactor, OverDisplacement };
PathMismatch chordMismatch(const PathEnergy& a, const PathEnergy& b, ChordWork work = ChordWork::OverLoadFactor);
/// `dp`: the path parameter's change from a to b; uses a.loadRate and b.loadRate.
PathMismatch tangentMismatch(const PathEnergy& a, const PathEnergy& b, double dp);

}  // namespace jetshell
