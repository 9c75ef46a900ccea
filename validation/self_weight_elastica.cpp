#include "validation/self_weight_elastica.h"

#include <cmath>

namespace jetshell::validation {
namespace {

/// Integrates from s = 0 with θ'(0) = kappa0 (q = w / G); returns θ'(l) and the tip (x, drop).
double shoot(double length, double q, double kappa0, double& x, double& drop) {
  constexpr int kSteps = 4000;
  const double h = length / kSteps;
  // State: θ, θ', x, drop; s is carried separately (the load term depends on it).
  auto rate = [&](double s, const double* y, double* dy) {
    dy[0] = y[1];
    dy[1] = -q * (length - s) * std::cos(y[0]);
    dy[2] = std::cos(y[0]);
    dy[3] = std::sin(y[0]);
  };
  double y[4] = {0.0, kappa0, 0.0, 0.0};
  for (int i = 0; i < kSteps; ++i) {
    const double s = i * h;
    double k1[4], k2[4], k3[4], k4[4], t[4];
    rate(s, y, k1);
    for (int c = 0; c < 4; ++c) t[c] = y[c] + 0.5 * h * k1[c];
    rate(s + 0.5 * h, t, k2);
    for (int c = 0; c < 4; ++c) t[c] = y[c] + 0.5 * h * k2[c];
    rate(s + 0.5 * h, t, k3);
    for (int c = 0; c < 4; ++c) t[c] = y[c] + h * k3[c];
    rate(s + h, t, k4);
    for (int c = 0; c < 4; ++c) y[c] += h / 6.0 * (k1[c] + 2.0 * k2[c] + 2.0 * k3[c] + k4[c]);
  }
  x = y[2];
  drop = y[3];
  return y[1];
}

}  // namespace

ElasticaTip selfWeightElastica(double length, double weightPerLength, double rigidity) {
  const double q = weightPerLength / rigidity;
  // θ'(l) rises with θ'(0); θ'(0) = M(0)/G lies in [0, q l²/2] (the moment of the weight about the clamp).
  double lo = 0.0, hi = 0.5 * q * length * length;
  ElasticaTip tip;
  for (int it = 0; it < 200 && hi - lo > 1e-13 * (1.0 + hi); ++it) {
    const double mid = 0.5 * (lo + hi);
    (shoot(length, q, mid, tip.x, tip.drop) < 0.0 ? lo : hi) = mid;
  }
  shoot(length, q, 0.5 * (lo + hi), tip.x, tip.drop);
  tip.chordAngle = std::atan2(tip.drop, tip.x);
  return tip;
}

double rigidityForChordAngle(double length, double weightPerLength, double chordAngle) {
  // The chord angle falls as G grows; bracket G between a droop past 89° and one below 0.01°.
  const double scale = weightPerLength * length * length * length;
  double lo = std::log(scale * 1e-4), hi = std::log(scale * 1e4);
  for (int it = 0; it < 200 && hi - lo > 1e-14; ++it) {
    const double mid = 0.5 * (lo + hi);
    (selfWeightElastica(length, weightPerLength, std::exp(mid)).chordAngle > chordAngle ? lo : hi) = mid;
  }
  return std::exp(0.5 * (lo + hi));
}

double peirceBendingLength(double length, double chordAngle) {
  return length * std::cbrt(std::cos(0.5 * chordAngle) / (8.0 * std::tan(chordAngle)));
}

}  // namespace jetshell::validation
