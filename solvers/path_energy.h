// The energy identity of a path of equilibria, which tells a step that followed the path from one that jumped
// to another branch (LoadJump, solvers/path_control.h).
//
// Along a continuous path of equilibria x(p), λ(p) (p the path parameter: λ itself under load control, the arc
// length or τ under path control) dE/dp = ∂E/∂x · dx/dp + ∂E/∂λ · dλ/dp = ∂E/∂λ · dλ/dp, since ∂E/∂x = 0 on the
// free dofs (∂E/∂λ moves the prescribed positions with λ). So a step's change of potential energy must match the
// integral of ∂E/∂λ dλ/dp over the step, which the trapezoid rule gives to O(Δp³). The energy of dead loads on
// absolute positions would drown the difference, so ∂E/∂λ is split into h = ∂E/∂λ − ∂E/∂λ at the path's start
// positions (the loads' work on the displacements, integrated in p) and the rest, a function of λ alone (dead
// loads: a constant), integrated in λ: exact for a path whose λ turns within the step (a limit point).
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
  double loadRate = 1.0;  // dλ/dp there (1 under load control, where p = λ)
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

/// `dp`: the path parameter's change from a to b (load control: b.lambda − a.lambda).
PathMismatch pathMismatch(const PathEnergy& a, const PathEnergy& b, double dp);

}  // namespace jetshell
