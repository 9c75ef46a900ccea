#include "tools/fit/material_mapping.h"

#include "core/mesh.h"

#include <ceres/jet.h>

#include <algorithm>
#include <array>

namespace jetshell {
namespace {

using Jet = ceres::Jet<double, kMaxFitParameters>;

constexpr int kOutputs = 9;
/// Output k of the formulas sets these term parameters (those whose term is active): the elastic moduli live in
/// the elastic terms and the stiffness-damping terms.
const std::array<std::vector<TermParameter>, kOutputs> kTargets = {
    std::vector<TermParameter>{{"membrane", "lambda"}, {"membrane_damping", "lambda"}},
    std::vector<TermParameter>{{"membrane", "mu"}, {"membrane_damping", "mu"}},
    std::vector<TermParameter>{{"bending", "alpha"}, {"bending_damping", "alpha"}},
    std::vector<TermParameter>{{"bending", "beta"}, {"bending_damping", "beta"}},
    std::vector<TermParameter>{{"gravity", "density"}},
    std::vector<TermParameter>{{"inertia", "density"}},
    std::vector<TermParameter>{{"mass_damping", "alpha_R"}},
    std::vector<TermParameter>{{"membrane_damping", "beta_R"}, {"bending_damping", "beta_R"}},
    std::vector<TermParameter>{{"nodal_forces", "scale"}}};

/// The outputs as Jets, with the fitted inputs seeded (input k of `names` → derivative slot k):
///   0-3 λ, μ, α, β; 4 ρ_A0 · gravityScale (gravity: its weight); 5 ρ_A0 (inertia);
///   6 α_R ρ_A0 / ρ_A0(base) (mass damping: its masses were lumped at the base density); 7 β_R; 8 loadScale.
std::array<Jet, kOutputs> outputs(const MaterialBase& base, const std::vector<std::string>& names,
                                  const Eigen::VectorXd& q) {
  auto input = [&](const std::string& name, double baseValue) {
    const auto it = std::find(names.begin(), names.end(), name);
    if (it == names.end()) return Jet(baseValue);
    const int k = static_cast<int>(it - names.begin());
    return Jet(q[k], k);
  };
  std::array<Jet, 5> shell;
  if (base.isotropic) {
    const ShellMaterialValues<Jet> m =
        shellMaterialFrom3dIsotropic(input("youngsModulus", base.youngsModulus), input("poissonRatio", base.poissonRatio),
                                     input("volumeDensity", base.volumeDensity), input("thickness", base.thickness));
    shell = {m.membraneLambda, m.membraneMu, m.bendingAlpha, m.bendingBeta, m.density};
  } else {
    const ShellMaterialParams& s = base.shell;
    shell = {input("membraneLambda", s.membraneLambda), input("membraneMu", s.membraneMu),
             input("bendingAlpha", s.bendingAlpha), input("bendingBeta", s.bendingBeta), input("density", s.density)};
  }
  const Jet& rho = shell[4];
  const double rhoBase = base.shell.density > 0.0 ? base.shell.density : 1.0;
  return {shell[0], shell[1], shell[2], shell[3],
          rho * input("gravityScale", 1.0),
          rho,
          input("massDampingCoefficient", base.shell.massDampingCoefficient) * rho / rhoBase,
          input("stiffnessDampingCoefficient", base.shell.stiffnessDampingCoefficient),
          input("loadScale", 1.0)};
}

/// Structural dependence of output k on a fitted name.
bool dependsOn(const MaterialBase& base, int output, const std::string& name) {
  const bool density = base.isotropic ? (name == "thickness" || name == "volumeDensity") : name == "density";
  switch (output) {
    case 4: return density || name == "gravityScale";
    case 5: return density;
    case 6: return density || name == "massDampingCoefficient";
    case 7: return name == "stiffnessDampingCoefficient";
    case 8: return name == "loadScale";
    default:
      if (!base.isotropic) return fittableMaterialNames(base)[static_cast<std::size_t>(output)] == name;
      return name == "youngsModulus" || name == "poissonRatio" || name == "thickness";
  }
}

}  // namespace

ParameterMapping materialMapping(const MaterialBase& base, const std::vector<std::string>& names,
                                 const std::vector<std::string>& labels, const Objective& objective) {
  if (names.empty()) throw InputError("fit: no parameter to fit");
  if (names.size() > static_cast<std::size_t>(kMaxFitParameters))
    throw InputError(labels[kMaxFitParameters] + ": at most " + std::to_string(kMaxFitParameters) +
                     " material parameters can be fitted at once");
  const std::vector<std::string> fittable = fittableMaterialNames(base);
  for (std::size_t k = 0; k < names.size(); ++k) {
    if (namedLoad(names[k]).empty() && std::find(fittable.begin(), fittable.end(), names[k]) == fittable.end()) {
      std::string list;
      for (const std::string& f : fittable) list += (list.empty() ? "" : ", ") + f;
      throw InputError(labels[k] + " = \"" + names[k] + "\": not fittable for this actor's material, which is given " +
                       (base.isotropic ? "as youngsModulus, poissonRatio, thickness, volumeDensity"
                                       : "by its shell parameters") + " (fittable: " + list + ")");
    }
    if (std::find(names.begin(), names.begin() + static_cast<std::ptrdiff_t>(k), names[k]) !=
        names.begin() + static_cast<std::ptrdiff_t>(k))
      throw InputError(labels[k] + " = \"" + names[k] + "\": fitted twice");
  }
  // The term parameters whose term is active and whose output some fitted name reaches (output index each).
  std::vector<int> used;
  ParameterMapping m;
  std::vector<char> effective(names.size(), 0);
  for (int o = 0; o < kOutputs; ++o) {
    for (const TermParameter& t : kTargets[static_cast<std::size_t>(o)]) {
      const EnergyTermPtr term = objective.term(t.term);
      if (!term) continue;
      bool reached = false;
      for (std::size_t k = 0; k < names.size(); ++k)
        if (dependsOn(base, o, names[k])) {
          reached = true;
          effective[k] = 1;
        }
      if (!reached) continue;
      const std::vector<std::string> have = term->parameterNames();
      if (std::find(have.begin(), have.end(), t.name) == have.end())
        throw InputError("fit: term '" + t.term + "' does not expose the parameter '" + t.name +
                         "' (it cannot be differentiated with respect to it yet)");
      used.push_back(o);
      m.termParameters.push_back(t);
    }
  }
  // Named load scales: one term parameter each, value q_k (the dependence is the identity).
  std::vector<std::pair<int, int>> namedRows;  // (row in values, fitted index)
  for (std::size_t k = 0; k < names.size(); ++k) {
    const std::string load = namedLoad(names[k]);
    if (load.empty()) continue;
    const EnergyTermPtr term = objective.term("nodal_forces");
    const std::vector<std::string> have = term ? term->parameterNames() : std::vector<std::string>{};
    if (std::find(have.begin(), have.end(), "scale/" + load) == have.end()) continue;  // no load to scale
    effective[k] = 1;
    namedRows.emplace_back(static_cast<int>(m.termParameters.size()), static_cast<int>(k));
    m.termParameters.push_back({"nodal_forces", "scale/" + load});
  }
  for (std::size_t k = 0; k < names.size(); ++k)
    if (!effective[k])
      throw InputError(labels[k] + " = \"" + names[k] + "\": has no effect on this problem (the terms it sets are "
                       "not active: no gravity, no load, no inertia or damping in a static scene, or a coefficient "
                       "that is 0 in the scene)");

  m.numParameters = static_cast<int>(names.size());
  const std::size_t rows = m.termParameters.size();
  m.map = [base, names, used, namedRows, rows](const Eigen::VectorXd& q, Eigen::VectorXd& values,
                                               Eigen::MatrixXd* jacobian) {
    const std::array<Jet, kOutputs> out = outputs(base, names, q);
    const int Q = static_cast<int>(names.size());
    values.resize(static_cast<Eigen::Index>(rows));
    if (jacobian) jacobian->setZero(static_cast<Eigen::Index>(rows), Q);
    for (const auto& [row, k] : namedRows) {
      values[row] = q[k];
      if (jacobian) (*jacobian)(row, k) = 1.0;
    }
    for (std::size_t i = 0; i < used.size(); ++i) {
      const Jet& v = out[static_cast<std::size_t>(used[i])];
      values[static_cast<Eigen::Index>(i)] = v.a;
      if (jacobian)
        for (int k = 0; k < Q; ++k) (*jacobian)(static_cast<Eigen::Index>(i), k) = v.v[k];
    }
  };
  return m;
}

}  // namespace jetshell
