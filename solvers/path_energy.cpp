#include "solvers/path_energy.h"

#include "solvers/statics.h"

#include <algorithm>
#include <cmath>

namespace jetshell {

PathEnergy pathEnergy(Objective& objective, const LoadFactorHooks& loads, const Eigen::VectorXd& x, double lambda,
                      const Eigen::VectorXd& start, const EvalOptions& options, double loadRate) {
  const double h = 1e-6 * std::max(1.0, std::abs(lambda));
  // ∂E/∂λ by a forward difference (λ − h may be out of a load's range: the weight refused λ < 0 until session 43);
  // its O(h) error is far below LoadJump's threshold. Returns the slope and, in *energy, E itself at λ (the
  // equilibrium's energy: no separate evaluation).
  auto slope = [&](const Eigen::VectorXd& at, double* energy) {
    Eigen::VectorXd a = at, b = at;
    objective.applyPrescribed(lambda, a);
    loads.set(lambda);
    const double ea = objective.evaluate(a, nullptr, false, options);
    objective.applyPrescribed(lambda + h, b);
    loads.set(lambda + h);
    const double eb = objective.evaluate(b, nullptr, false, options);
    if (energy != nullptr) *energy = ea;
    return (eb - ea) / h;
  };
  PathEnergy p;
  p.lambda = lambda;
  p.loadRate = loadRate;
  p.slope = slope(x, &p.energy);
  p.referenceSlope = slope(start, nullptr);
  loads.set(lambda);
  return p;
}

PathMismatch chordMismatch(const PathEnergy& a, const PathEnergy& b, ChordWork work) {
  const double dl = b.lambda - a.lambda, ha = a.slope - a.referenceSlope, hb = b.slope - b.referenceSlope;
  PathMismatch m;
  m.released = 0.5 * (a.slope + b.slope) * dl - (b.energy - a.energy);
  m.work = work == ChordWork::OverLoadFactor ? 0.5 * std::abs(dl) * (std::abs(ha) + std::abs(hb))
                                             : 0.5 * std::abs(hb - ha) * (std::abs(a.lambda) + std::abs(b.lambda));
  return m;
}

PathMismatch tangentMismatch(const PathEnergy& a, const PathEnergy& b, double dp) {
  const double wa = (a.slope - a.referenceSlope) * a.loadRate, wb = (b.slope - b.referenceSlope) * b.loadRate;
  PathMismatch m;
  m.released = 0.5 * dp * (wa + wb) + 0.5 * (a.referenceSlope + b.referenceSlope) * (b.lambda - a.lambda) -
               (b.energy - a.energy);
  m.work = 0.5 * std::abs(dp) * (std::abs(wa) + std::abs(wb));
  return m;
}

}  // namespace jetshell
