#include "core/mesh.h"
#include "energies/shell/material.h"

#include <catch2/catch.hpp>

#include <limits>

using namespace jetshell;

TEST_CASE("material: defaults are the spec's ShellMaterialParams") {
  const ShellMaterialParams m;
  CHECK(m.membraneLambda == 300.0);
  CHECK(m.membraneMu == 400.0);
  CHECK(m.bendingAlpha == 2e-5);
  CHECK(m.bendingBeta == 7e-5);
  CHECK(m.density == 1.0);
  CHECK(m.massDampingCoefficient == 0.0);
  CHECK(m.stiffnessDampingCoefficient == 0.0);
  CHECK_NOTHROW(validate(m));
}

TEST_CASE("material: ShellMaterialParamsFrom3dIsotropic follows the spec's formulas") {
  // The slit-plate example of the spec's page: E 210 MPa, ν 0.3 (ν 0 below), ρ0 1000 kg/m³, h 3 mm.
  const double E = 210e6, nu = 0.3, rho0 = 1000.0, h = 0.003;
  const ShellMaterialParams m = ShellMaterialParamsFrom3dIsotropic(E, nu, rho0, h);
  const double d = 1.0 - nu * nu;
  CHECK(m.membraneLambda == Approx(h * E * nu / d).epsilon(1e-15));
  CHECK(m.membraneMu == Approx(h * E / (2.0 * (1.0 + nu))).epsilon(1e-15));
  CHECK(m.bendingAlpha == Approx(h * h * h * E * nu / (12.0 * d)).epsilon(1e-15));
  CHECK(m.bendingBeta == Approx(h * h * h * E * (1.0 - nu) / (12.0 * d)).epsilon(1e-15));
  CHECK(m.density == Approx(h * rho0).epsilon(1e-15));
  // Hand-computed values: λ = 0.003·210e6·0.3/0.91 = 207692.3077 N/m, μ = 242307.6923 N/m.
  CHECK(m.membraneLambda == Approx(207692.30769230769).epsilon(1e-12));
  CHECK(m.membraneMu == Approx(242307.69230769231).epsilon(1e-12));
  // Consistency of the plate theory: α + β = D = Eh³/(12(1−ν²)), and α/β = ν/(1−ν).
  CHECK(m.bendingAlpha + m.bendingBeta == Approx(E * h * h * h / (12.0 * d)).epsilon(1e-14));
  CHECK(m.bendingAlpha / m.bendingBeta == Approx(nu / (1.0 - nu)).epsilon(1e-14));
  // The membrane/bending ratio is h²/12 for both Lamé-like pairs.
  CHECK(m.bendingAlpha / m.membraneLambda == Approx(h * h / 12.0).epsilon(1e-14));
  CHECK_NOTHROW(validate(m));

  const ShellMaterialParams zeroNu = ShellMaterialParamsFrom3dIsotropic(E, 0.0, rho0, h);
  CHECK(zeroNu.membraneLambda == 0.0);
  CHECK(zeroNu.bendingAlpha == 0.0);
  CHECK(zeroNu.membraneMu == Approx(h * E / 2.0));
}

TEST_CASE("material: invalid 3D parameters are rejected with the field's name") {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  CHECK_THROWS_WITH(ShellMaterialParamsFrom3dIsotropic(0.0, 0.3, 1000, 0.01), Catch::Contains("youngsModulus"));
  CHECK_THROWS_WITH(ShellMaterialParamsFrom3dIsotropic(nan, 0.3, 1000, 0.01), Catch::Contains("youngsModulus"));
  CHECK_THROWS_WITH(ShellMaterialParamsFrom3dIsotropic(1e5, 0.5, 1000, 0.01), Catch::Contains("poissonRatio"));
  CHECK_THROWS_WITH(ShellMaterialParamsFrom3dIsotropic(1e5, -1.0, 1000, 0.01), Catch::Contains("poissonRatio"));
  CHECK_THROWS_WITH(ShellMaterialParamsFrom3dIsotropic(1e5, 0.3, -1.0, 0.01), Catch::Contains("density"));
  CHECK_THROWS_WITH(ShellMaterialParamsFrom3dIsotropic(1e5, 0.3, 1000, 0.0), Catch::Contains("thickness"));
  CHECK_THROWS_AS(ShellMaterialParamsFrom3dIsotropic(1e5, 0.3, 1000, -0.01), InputError);
  CHECK_NOTHROW(ShellMaterialParamsFrom3dIsotropic(1e5, -0.5, 0.0, 0.01));
}

TEST_CASE("material: validate names the offending field") {
  auto rejects = [](void (*edit)(ShellMaterialParams&), const char* field) {
    ShellMaterialParams m;
    edit(m);
    CHECK_THROWS_WITH(validate(m, "actor.material"), Catch::Contains(std::string("actor.material.") + field));
  };
  rejects([](ShellMaterialParams& m) { m.membraneMu = -1.0; }, "membraneMu");
  rejects([](ShellMaterialParams& m) { m.membraneLambda = -500.0; }, "membraneLambda");  // λ + μ <= 0
  rejects([](ShellMaterialParams& m) { m.membraneLambda = std::numeric_limits<double>::infinity(); },
          "membraneLambda");
  rejects([](ShellMaterialParams& m) { m.bendingBeta = -1e-5; }, "bendingBeta");
  rejects([](ShellMaterialParams& m) { m.bendingAlpha = -1e-4; }, "bendingAlpha");  // α + β <= 0
  rejects([](ShellMaterialParams& m) { m.density = -1.0; }, "density");
  rejects([](ShellMaterialParams& m) { m.massDampingCoefficient = -0.1; }, "massDampingCoefficient");
  rejects([](ShellMaterialParams& m) { m.stiffnessDampingCoefficient = std::nan(""); },
          "stiffnessDampingCoefficient");
  // Exactly the positive-definite energies pass: μ > 0, λ + μ > 0, β > 0, 2α + β > 0.
  rejects([](ShellMaterialParams& m) { m.membraneMu = 0.0; m.membraneLambda = -100.0; }, "membraneMu");
  rejects([](ShellMaterialParams& m) { m.membraneMu = 0.0; m.membraneLambda = 100.0; }, "membraneMu");
  rejects([](ShellMaterialParams& m) { m.membraneLambda = -m.membraneMu; }, "membraneLambda");
  rejects([](ShellMaterialParams& m) { m.bendingBeta = 0.0; }, "bendingBeta");
  rejects([](ShellMaterialParams& m) { m.bendingAlpha = -0.6 * m.bendingBeta; }, "bendingAlpha");  // α + β > 0 only
  rejects([](ShellMaterialParams& m) { m.bendingAlpha = -0.5 * m.bendingBeta; }, "bendingAlpha");
  ShellMaterialParams nearBounds;
  nearBounds.membraneLambda = -0.99 * nearBounds.membraneMu;
  nearBounds.bendingAlpha = -0.49 * nearBounds.bendingBeta;
  CHECK_NOTHROW(validate(nearBounds));
  ShellMaterialParams negativeLambda;
  negativeLambda.membraneLambda = -100.0;  // auxetic but still positive definite (λ + μ > 0)
  CHECK_NOTHROW(validate(negativeLambda));
}
