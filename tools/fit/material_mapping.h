// From user-level material parameters (E, ν, h, ρ0 of a 3D isotropic material, or the shell parameters λ, μ,
// α, β, ρ_A0 themselves) to the parameters of the active terms, with the Jacobian from Ceres Jets through the
// same formulas the scene reader uses (energies/shell/material.h) — no hand derivatives.
//
//   shell output     term parameter        depends on (isotropic base)   (shell base)
//   λ                membrane.lambda       E, ν, h                        membraneLambda
//   μ                membrane.mu           E, ν, h                        membraneMu
//   α                bending.alpha         E, ν, h                        bendingAlpha
//   β                bending.beta          E, ν, h                        bendingBeta
//   ρ_A0             gravity.density       h, ρ0                          density
// α and β also set boundary_rules.alpha/beta when a scene's edge rules add that correction term
// (tools/scene/scene_edge_rules.h). An output is set only when its term is active (a scene without gravity has no
// density to fit through).
//
// Inputs: the base material (the values not fitted), the fitted names in order, the objective (active terms).
// Outputs: a ParameterMapping (tools/fit/static_fit_problem.h).
#pragma once

#include "energies/shell/material.h"
#include "solvers/objective.h"
#include "tools/fit/static_fit_problem.h"

#include <string>
#include <vector>

namespace jetshell {

/// At most this many material parameters are fitted at once (the Jet width).
constexpr int kMaxFitParameters = 8;

struct MaterialBase {
  bool isotropic = false;  // given as youngsModulus, poissonRatio, thickness, volumeDensity
  double youngsModulus = 0.0, poissonRatio = 0.0, thickness = 0.0, volumeDensity = 0.0;
  ShellMaterialParams shell;  // the shell parameters (derived from the above when isotropic)
};

/// The names that can be fitted with this base: youngsModulus, poissonRatio, thickness, volumeDensity for an
/// isotropic base; membraneLambda, membraneMu, bendingAlpha, bendingBeta, density otherwise.
std::vector<std::string> fittableMaterialNames(const MaterialBase& base);

/// The current value of a fittable name in the base.
double materialBaseValue(const MaterialBase& base, const std::string& name);

/// The mapping. Throws InputError naming the parameter (by `labels`, same order as names) when a name is not
/// fittable for this base, repeated, or has no effect on any active term, or when more than kMaxFitParameters
/// are given.
ParameterMapping materialMapping(const MaterialBase& base, const std::vector<std::string>& names,
                                 const std::vector<std::string>& labels, const Objective& objective);

}  // namespace jetshell
