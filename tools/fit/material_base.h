// The material a fit starts from, as the scene gives it (E, ν, h, ρ0 of an isotropic material, or the shell
// parameters themselves), and the names that can be fitted with it. Plain data and name lookups: the fit-file
// reader (tools/fit/fit_file.h) checks names with it and builds with the other parsers; the mapping to term
// parameters (tools/fit/material_mapping.h) needs the solver's objective.
#pragma once

#include "energies/shell/material.h"

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
/// isotropic base; membraneLambda, membraneMu, bendingAlpha, bendingBeta, density otherwise; and with either,
/// massDampingCoefficient, stiffnessDampingCoefficient, gravityScale, loadScale.
std::vector<std::string> fittableMaterialNames(const MaterialBase& base);

/// The name under which materialMapping takes the scale of the named load `load` ("loadScale/<load>"): it sets
/// the load term's parameter "scale/<load>" (NodalForceTerm::addNamedPart), exactly linearly.
std::string namedLoadScale(const std::string& load);
/// The load a name made by namedLoadScale scales, or "" for any other name.
std::string namedLoad(const std::string& name);

/// The current value of a fittable name in the base.
double materialBaseValue(const MaterialBase& base, const std::string& name);

}  // namespace jetshell
