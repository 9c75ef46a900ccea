#include "tools/fit/material_mapping.h"

#include "core/mesh.h"

#include <ceres/jet.h>

#include <algorithm>
#include <array>

namespace jetshell {
namespace {

using Jet = ceres::Jet<double, kMaxFitParameters>;

const std::vector<std::string> kIsotropic = {"youngsModulus", "poissonRatio", "thickness", "volumeDensity"};
const std::vector<std::string> kShell = {"membraneLambda", "membraneMu", "bendingAlpha", "bendingBeta", "density"};
/// Output k of the material formulas sets these term parameters (those whose term is active): the bending
/// moduli live in the bending term and in the boundary-rule correction of a scene's edge rules.
const std::array<std::vector<TermParameter>, 5> kTargets = {
    std::vector<TermParameter>{{"membrane", "lambda"}},
    std::vector<TermParameter>{{"membrane", "mu"}},
    std::vector<TermParameter>{{"bending", "alpha"}, {"boundary_rules", "alpha"}},
    std::vector<TermParameter>{{"bending", "beta"}, {"boundary_rules", "beta"}},
    std::vector<TermParameter>{{"gravity", "density"}}};

/// The five shell outputs as Jets, with the fitted inputs seeded (input k of `names` → derivative slot k).
std::array<Jet, 5> outputs(const MaterialBase& base, const std::vector<std::string>& names, const Eigen::VectorXd& q) {
  auto input = [&](const std::string& name, double baseValue) {
    const auto it = std::find(names.begin(), names.end(), name);
    if (it == names.end()) return Jet(baseValue);
    const int k = static_cast<int>(it - names.begin());
    return Jet(q[k], k);
  };
  if (base.isotropic) {
    const ShellMaterialValues<Jet> m =
        shellMaterialFrom3dIsotropic(input("youngsModulus", base.youngsModulus), input("poissonRatio", base.poissonRatio),
                                     input("volumeDensity", base.volumeDensity), input("thickness", base.thickness));
    return {m.membraneLambda, m.membraneMu, m.bendingAlpha, m.bendingBeta, m.density};
  }
  const ShellMaterialParams& s = base.shell;
  return {input("membraneLambda", s.membraneLambda), input("membraneMu", s.membraneMu),
          input("bendingAlpha", s.bendingAlpha), input("bendingBeta", s.bendingBeta), input("density", s.density)};
}

/// Structural dependence of output k on a fitted name.
bool dependsOn(const MaterialBase& base, int output, const std::string& name) {
  if (!base.isotropic) return kShell[static_cast<std::size_t>(output)] == name;
  if (output == 4) return name == "thickness" || name == "volumeDensity";
  return name != "volumeDensity";
}

}  // namespace

std::vector<std::string> fittableMaterialNames(const MaterialBase& base) { return base.isotropic ? kIsotropic : kShell; }

double materialBaseValue(const MaterialBase& base, const std::string& name) {
  if (name == "youngsModulus") return base.youngsModulus;
  if (name == "poissonRatio") return base.poissonRatio;
  if (name == "thickness") return base.thickness;
  if (name == "volumeDensity") return base.volumeDensity;
  if (name == "membraneLambda") return base.shell.membraneLambda;
  if (name == "membraneMu") return base.shell.membraneMu;
  if (name == "bendingAlpha") return base.shell.bendingAlpha;
  if (name == "bendingBeta") return base.shell.bendingBeta;
  if (name == "density") return base.shell.density;
  throw InputError("no material parameter named '" + name + "'");
}

ParameterMapping materialMapping(const MaterialBase& base, const std::vector<std::string>& names,
                                 const std::vector<std::string>& labels, const Objective& objective) {
  if (names.empty()) throw InputError("fit: no parameter to fit");
  if (names.size() > static_cast<std::size_t>(kMaxFitParameters))
    throw InputError(labels[kMaxFitParameters] + ": at most " + std::to_string(kMaxFitParameters) +
                     " material parameters can be fitted at once");
  const std::vector<std::string> fittable = fittableMaterialNames(base);
  for (std::size_t k = 0; k < names.size(); ++k) {
    if (std::find(fittable.begin(), fittable.end(), names[k]) == fittable.end()) {
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
  for (int o = 0; o < 5; ++o) {
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
  for (std::size_t k = 0; k < names.size(); ++k)
    if (!effective[k])
      throw InputError(labels[k] + " = \"" + names[k] + "\": has no effect on this static problem (the terms it "
                       "sets are not active)");

  m.numParameters = static_cast<int>(names.size());
  m.map = [base, names, used](const Eigen::VectorXd& q, Eigen::VectorXd& values, Eigen::MatrixXd* jacobian) {
    const std::array<Jet, 5> out = outputs(base, names, q);
    const int Q = static_cast<int>(names.size());
    values.resize(static_cast<Eigen::Index>(used.size()));
    if (jacobian) jacobian->resize(static_cast<Eigen::Index>(used.size()), Q);
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
