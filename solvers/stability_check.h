// Whether an equilibrium is a minimum of the potential energy or a saddle, and which way is downhill from a
// saddle: shared by load control (solvers/statics.h) and dynamic relaxation (solvers/dynamic_relaxation.h), which
// both stop where the residual vanishes, and a symmetric start (a flat sheet or a straight column in compression)
// can keep them on a saddle (load control's Newton steps keep the symmetry to the bit, relaxation to round-off).
//
// Inputs: the objective, the equilibrium x, the terms whose energy is the potential (all of a static system; the
// potential ones of a relaxation, without inertia and damping), and the escape step as a fraction of the mesh's
// mean edge length. Outputs: the count of negative eigenvalues of the exact Hessian there (the negative pivots of
// its LDLᵀ factor, solvers/indefinite_factor.h) and, on a saddle, a step along negative curvature that descends.
#pragma once

#include "core/term.h"
#include "solvers/indefinite_factor.h"
#include "solvers/objective.h"

#include <Eigen/Core>

namespace jetshell {

struct Stability {
  int negativeEigenvalues = -1;  // -1: unknown (the factorization failed)
  double energy = 0.0;           // the selected terms' energy at x
  /// With negative eigenvalues: d = Pᵀ L⁻ᵀ u (u sums the negative pivots' unit vectors, so dᵀ H d = Σ D_ii < 0),
  /// prescribed dofs zeroed, scaled so that its largest vertex move is step × the length scale, and turned to
  /// descend (gradient · d ≤ 0). Empty when there is none or it is not finite.
  Eigen::VectorXd downhill;
};

/// Factors the exact, unprojected Hessian of the selected terms at x with `factor` (analysed once per Hessian
/// pattern, so a caller keeps one factor for a whole path) and counts its negative eigenvalues. It assembles into
/// the objective's Hessian: a solver that reads the assembled matrix afterwards must assemble again.
Stability assessStability(Objective& objective, IndefiniteFactor& factor, const Eigen::VectorXd& x,
                          DerivativePath path, double step, TermSelection selection = TermSelection::All);

}  // namespace jetshell
