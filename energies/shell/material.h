// Shell material parameters (the spec's ShellMaterialParams) and their derivation from 3D isotropic data.
#pragma once

#include <string>

namespace jetshell {

struct ShellMaterialParams {
  double membraneLambda = 300.0;             // Pa·m, 2D Lamé first parameter
  double membraneMu = 400.0;                 // Pa·m, 2D Lamé second parameter
  double bendingAlpha = 2e-5;                // Pa·m³
  double bendingBeta = 7e-5;                 // Pa·m³
  double density = 1.0;                      // kg/m², mass per unit reference area ρ_A0
  double massDampingCoefficient = 0.0;       // 1/s, α_R
  double stiffnessDampingCoefficient = 0.0;  // s, β_R
};

/// The formulas of ShellMaterialParamsFrom3dIsotropic on any scalar type, unchecked: with Ceres Jets they give
/// the derivatives of (λ, μ, α, β, ρ_A0) with respect to (E, ν, ρ0, h) that fitting needs.
template <typename T>
struct ShellMaterialValues {
  T membraneLambda, membraneMu, bendingAlpha, bendingBeta, density;
};
template <typename T>
ShellMaterialValues<T> shellMaterialFrom3dIsotropic(const T& E, const T& nu, const T& rho0, const T& h) {
  const T d = T(1.0) - nu * nu;
  const T h3 = h * h * h;
  return {h * E * nu / d, h * E / (T(2.0) * (T(1.0) + nu)), h3 * E * nu / (T(12.0) * d),
          h3 * E * (T(1.0) - nu) / (T(12.0) * d), h * rho0};
}

/// λ = hEν/(1−ν²), μ = hE/(2(1+ν)), α = h³Eν/(12(1−ν²)), β = h³E(1−ν)/(12(1−ν²)), ρ_A0 = hρ0.
/// Throws InputError for E <= 0, ν outside (−1, 0.5), ρ0 < 0, h <= 0 or non-finite values, and when E·h or E·h³
/// leaves a double's range (μ or β not finite and > 0: h = 1e-200 gives β = 0). Messages begin with `where`.
ShellMaterialParams ShellMaterialParamsFrom3dIsotropic(
    double youngsModulus, double poissonRatio, double density3d, double thickness,
    const std::string& where = "ShellMaterialParamsFrom3dIsotropic");

/// Throws InputError naming the field (prefixed by `where`) when a parameter is non-finite, a density or damping
/// coefficient negative, or an energy not positive definite: it accepts exactly μ > 0, λ + μ > 0, β > 0 and
/// 2α + β > 0.
void validate(const ShellMaterialParams& m, const std::string& where = "material");

}  // namespace jetshell
