// From user-level material parameters (E, ν, h, ρ0 of a 3D isotropic material, or the shell parameters λ, μ,
// α, β, ρ_A0 themselves; the damping coefficients α_R, β_R; scales on gravity and on the applied loads) to the
// parameters of the active terms, with the Jacobian from Ceres Jets through the same formulas the scene reader
// uses (energies/shell/material.h) — no hand derivatives.
//
//   output               term parameters                                   depends on (isotropic)  (shell base)
//   λ, μ                 membrane.lambda/mu, membrane_damping.lambda/mu     E, ν, h                 membraneLambda/Mu
//   α, β                 bending.alpha/beta, bending_damping.alpha/beta     E, ν, h                 bendingAlpha/Beta
//   ρ_A0 · gravityScale  gravity.density                                   h, ρ0, gravityScale     density, gravityScale
//   ρ_A0                 inertia.density                                   h, ρ0                   density
//   α_R ρ_A0/ρ_A0,scene  mass_damping.alpha_R (its masses are the scene's)  h, ρ0, α_R              density, α_R
//   β_R                  membrane_damping.beta_R, bending_damping.beta_R   β_R                     β_R
//   loadScale            nodal_forces.scale (all applied loads)            loadScale               loadScale
// α_R and β_R are named massDampingCoefficient and stiffnessDampingCoefficient, as in the scene's material. An
// output is set only when its term is active (a static scene has no inertia or damping; a scene without
// gravity has no weight to scale; a damping coefficient that is 0 in the scene builds no damping term).
//
// Inputs: the base material (the values not fitted), the fitted names in order, the objective (active terms).
// Outputs: a ParameterMapping (tools/fit/fit_problem.h).
#pragma once

#include "energies/shell/material.h"
#include "tools/fit/material_base.h"
#include "solvers/objective.h"
#include "tools/fit/fit_problem.h"

#include <string>
#include <vector>

namespace jetshell {

/// The mapping. Throws InputError naming the parameter (by `labels`, same order as names) when a name is not
/// fittable for this base, repeated, or has no effect on any active term, or when more than kMaxFitParameters
/// are given.
ParameterMapping materialMapping(const MaterialBase& base, const std::vector<std::string>& names,
                                 const std::vector<std::string>& labels, const Objective& objective);

}  // namespace jetshell
