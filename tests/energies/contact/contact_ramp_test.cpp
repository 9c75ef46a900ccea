#include "energies/contact/contact_ramp.h"

#include <catch2/catch.hpp>

using namespace jetshell;

TEST_CASE("contact ramp: zero outside, C2 across both kinks, linear force deep inside", "[contact]") {
  const double delta = 1e-3;
  CHECK(contactRamp(-1e-4, delta) == 0.0);
  CHECK(contactRampForce(-1e-4, delta) == 0.0);
  // Value, first and second derivative continuous at p = 0 and p = δ (left/right limits agree).
  for (double kink : {0.0, delta}) {
    const double h = 1e-9;
    CHECK(contactRamp(kink - h, delta) == Approx(contactRamp(kink + h, delta)).margin(1e-15));
    CHECK(contactRampForce(kink - h, delta) == Approx(contactRampForce(kink + h, delta)).margin(1e-11));
    const double slopeLeft = (contactRampForce(kink - h, delta) - contactRampForce(kink - 2 * h, delta)) / h;
    const double slopeRight = (contactRampForce(kink + 2 * h, delta) - contactRampForce(kink + h, delta)) / h;
    CHECK(slopeLeft == Approx(slopeRight).margin(1e-5));
  }
  // r = R' and G' = p r by central differences inside each piece.
  for (double p : {0.3 * delta, 0.9 * delta, 3.0 * delta}) {
    const double h = 1e-8;
    CHECK((contactRamp(p + h, delta) - contactRamp(p - h, delta)) / (2 * h) ==
          Approx(contactRampForce(p, delta)).epsilon(1e-6));
    CHECK((contactRampMoment(p + h, delta) - contactRampMoment(p - h, delta)) / (2 * h) ==
          Approx(p * contactRampForce(p, delta)).epsilon(1e-6));
  }
  CHECK(contactRampForce(5 * delta, delta) == Approx(4.5 * delta));
}

TEST_CASE("contact ramp: friction primitive rises from a quadratic at zero slip to the slip length", "[contact]") {
  const double epsV = 0.01;
  CHECK(frictionPrimitive(0.0, epsV) == 0.0);
  // f0' = f1 in [0, 1], 1 beyond ε_v: friction saturates at μλ.
  auto f1 = [&](double y) {
    const double h = 1e-9;
    return (frictionPrimitive((y + h) * (y + h), epsV) - frictionPrimitive((y - h) * (y - h), epsV)) / (2 * h);
  };
  CHECK(f1(0.5 * epsV) == Approx(0.75).epsilon(1e-6));  // 2y/ε − y²/ε² at y = ε/2
  CHECK(f1(2 * epsV) == Approx(1.0).epsilon(1e-6));
  CHECK(f1(epsV * (1 - 1e-6)) == Approx(f1(epsV * (1 + 1e-6))).epsilon(1e-5));
  // A zero slip is differentiable with duals: the gradient there is zero, not NaN.
  using J = ceres::Jet<double, 3>;
  J u[3] = {J(0.0, 0), J(0.0, 1), J(0.0, 2)};
  const J f = frictionPrimitive(u[0] * u[0] + u[1] * u[1] + u[2] * u[2], epsV);
  CHECK(f.a == 0.0);
  for (int i = 0; i < 3; ++i) CHECK(f.v[i] == 0.0);
}
