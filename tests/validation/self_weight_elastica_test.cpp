#include "core/math_constants.h"
#include "validation/self_weight_elastica.h"

#include <catch2/catch.hpp>

#include <cmath>
#include <cstdio>

using jetshell::kPi;
using namespace jetshell::validation;

namespace {
}

TEST_CASE("self-weight elastica: small deflections follow the linear cantilever w l^4 / (8 G)", "[validation]") {
  const double l = 0.2, w = 0.5, G = 1e3;  // w l³ / G = 2e-6: linear
  const ElasticaTip tip = selfWeightElastica(l, w, G);
  CHECK(tip.drop == Approx(w * l * l * l * l / (8.0 * G)).epsilon(1e-5));
  CHECK(tip.x == Approx(l).epsilon(1e-9));
}

TEST_CASE("self-weight elastica: the 41.5 degree overhang and Peirce's bending length", "[validation]") {
  const double l = 0.05, w = 0.02;
  const double theta = 41.5 * kPi / 180.0;
  const double G = rigidityForChordAngle(l, w, theta);
  const ElasticaTip tip = selfWeightElastica(l, w, G);
  CHECK(tip.chordAngle == Approx(theta).epsilon(1e-9));
  // The shape depends only on w l³ / G: scaling l scales the tip.
  const ElasticaTip scaled = selfWeightElastica(2.0 * l, w, 8.0 * G);
  CHECK(scaled.x == Approx(2.0 * tip.x).epsilon(1e-9));
  CHECK(scaled.drop == Approx(2.0 * tip.drop).epsilon(1e-9));
  // ASTM D1388's rule c = l/2, G = w c³, is the elastica's to 0.1% at 41.5° (why the standard picks that angle);
  // Peirce's approximate c = l (cos(θ/2) / (8 tan θ))^(1/3) reads 5.8% stiffer.
  CHECK(w * l * l * l / 8.0 == Approx(G).epsilon(1e-3));
  const double c = peirceBendingLength(l, theta);
  CHECK(c == Approx(0.5 * l).epsilon(0.02));
  CHECK(w * c * c * c == Approx(G).epsilon(0.07));
  std::printf("elastica at 41.5 deg: w l^3 / G = %.12g, tip x / l = %.15g, drop / l = %.15g; Peirce G / elastica G = %.6f, "
              "(l/2) rule: %.6f\n",
              w * l * l * l / G, tip.x / l, tip.drop / l, w * c * c * c / G, w * l * l * l / 8.0 / G);
}
