#include "energies/shell/material.h"

#include "core/format.h"
#include "core/input_limits.h"
#include "core/mesh.h"

#include <cmath>
#include <sstream>

namespace jetshell {
namespace {

void require(bool ok, const std::string& where, const char* field, double value, const std::string& rule) {
  if (ok) return;
  std::ostringstream s;
  s << where << "." << field << " = " << value << ": " << rule;
  throw InputError(s.str());
}

}  // namespace

ShellMaterialParams ShellMaterialParamsFrom3dIsotropic(double E, double nu, double rho0, double h,
                                                       const std::string& w) {
  require(std::isfinite(E) && E > 0, w, "youngsModulus", E, "must be finite and > 0");
  require(std::isfinite(nu) && nu > -1.0 && nu < 0.5, w, "poissonRatio", nu, "must lie in (-1, 0.5)");
  require(std::isfinite(rho0) && rho0 >= 0, w, "density", rho0, "must be finite and >= 0");
  require(std::isfinite(h) && h > 0, w, "thickness", h, "must be finite and > 0");
  const ShellMaterialValues<double> v = shellMaterialFrom3dIsotropic(E, nu, rho0, h);
  // E h and E h³ can leave a double's range although E and h are each fine.
  const auto fine = [](double x) { return std::isfinite(x) && x > 0; };
  if (!fine(v.membraneMu) || !fine(v.bendingBeta) || !std::isfinite(v.density))
    throw InputError(w + ": youngsModulus " + formatNumber("%g", E) + " and thickness " + formatNumber("%g", h) +
                     " give a membrane stiffness mu = " + formatNumber("%g", v.membraneMu) +
                     " N/m and a bending stiffness beta = " + formatNumber("%g", v.bendingBeta) +
                     " N m, which must be finite and > 0 (E h and E h^3 out of a double's range)");
  ShellMaterialParams m;
  m.membraneLambda = v.membraneLambda;
  m.membraneMu = v.membraneMu;
  m.bendingAlpha = v.bendingAlpha;
  m.bendingBeta = v.bendingBeta;
  m.density = v.density;
  return m;
}

void validate(const ShellMaterialParams& m, const std::string& w) {
  // The energies are positive definite exactly when these hold. In 2D, splitting ε into its deviator and trace,
  // λ/2 (tr ε)² + μ tr(ε²) = μ |dev ε|² + (λ + μ)/2 (tr ε)²: μ > 0 and λ + μ > 0. Bending alike,
  // ½(α (tr κ)² + β tr(κ²)) = β/2 |dev κ|² + (2α + β)/4 (tr κ)²: β > 0 and 2α + β > 0.
  require(std::isfinite(m.membraneLambda), w, "membraneLambda", m.membraneLambda, "must be finite");
  require(std::isfinite(m.membraneMu) && m.membraneMu > 0, w, "membraneMu", m.membraneMu, "must be finite and > 0");
  require(m.membraneLambda + m.membraneMu > 0, w, "membraneLambda", m.membraneLambda,
          "must satisfy membraneLambda + membraneMu > 0");
  require(std::isfinite(m.bendingAlpha), w, "bendingAlpha", m.bendingAlpha, "must be finite");
  require(std::isfinite(m.bendingBeta) && m.bendingBeta > 0, w, "bendingBeta", m.bendingBeta, "must be finite and > 0");
  require(2.0 * m.bendingAlpha + m.bendingBeta > 0, w, "bendingAlpha", m.bendingAlpha,
          "must satisfy 2 bendingAlpha + bendingBeta > 0");
  require(std::isfinite(m.density) && m.density >= 0, w, "density", m.density, "must be finite and >= 0");
  const double maxDamping = inputLimits().maxDampingCoefficient;
  require(m.massDampingCoefficient >= 0 && m.massDampingCoefficient <= maxDamping, w, "massDampingCoefficient",
          m.massDampingCoefficient, "must lie in [0, " + formatNumber("%g", maxDamping) + "] (1/s)");
  require(m.stiffnessDampingCoefficient >= 0 && m.stiffnessDampingCoefficient <= maxDamping, w,
          "stiffnessDampingCoefficient", m.stiffnessDampingCoefficient,
          "must lie in [0, " + formatNumber("%g", maxDamping) + "] (s)");
}

}  // namespace jetshell
