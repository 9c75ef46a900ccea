#include "tools/fit/material_base.h"

#include "core/mesh.h"

namespace jetshell {
namespace {

const std::vector<std::string> kIsotropic = {"youngsModulus", "poissonRatio", "thickness", "volumeDensity"};
const std::vector<std::string> kShell = {"membraneLambda", "membraneMu", "bendingAlpha", "bendingBeta", "density"};
/// Fittable with either base: the damping coefficients and the load scales.
const std::vector<std::string> kCommon = {"massDampingCoefficient", "stiffnessDampingCoefficient", "gravityScale",
                                          "loadScale"};

}  // namespace

std::vector<std::string> fittableMaterialNames(const MaterialBase& base) {
  std::vector<std::string> names = base.isotropic ? kIsotropic : kShell;
  names.insert(names.end(), kCommon.begin(), kCommon.end());
  return names;
}

std::string namedLoadScale(const std::string& load) { return "loadScale/" + load; }

std::string namedLoad(const std::string& name) {
  const std::string prefix = "loadScale/";
  return name.rfind(prefix, 0) == 0 ? name.substr(prefix.size()) : std::string();
}

double materialBaseValue(const MaterialBase& base, const std::string& name) {
  if (!namedLoad(name).empty()) return 1.0;
  if (name == "youngsModulus") return base.youngsModulus;
  if (name == "poissonRatio") return base.poissonRatio;
  if (name == "thickness") return base.thickness;
  if (name == "volumeDensity") return base.volumeDensity;
  if (name == "membraneLambda") return base.shell.membraneLambda;
  if (name == "membraneMu") return base.shell.membraneMu;
  if (name == "bendingAlpha") return base.shell.bendingAlpha;
  if (name == "bendingBeta") return base.shell.bendingBeta;
  if (name == "density") return base.shell.density;
  if (name == "massDampingCoefficient") return base.shell.massDampingCoefficient;
  if (name == "stiffnessDampingCoefficient") return base.shell.stiffnessDampingCoefficient;
  if (name == "gravityScale" || name == "loadScale") return 1.0;
  throw InputError("no material parameter named '" + name + "'");
}

}  // namespace jetshell
