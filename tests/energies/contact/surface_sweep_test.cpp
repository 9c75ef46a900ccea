#include "energies/contact/surface_sweep.h"

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

using namespace jetshell;

namespace {

/// Single-vertex samples at the given points (a shell's contact samples, without faces).
struct Samples {
  ContactSampling sampling;
  Eigen::VectorXd x;
};

Samples samplesAt(const std::vector<Eigen::Vector3d>& points) {
  Samples s;
  s.sampling.table.width = 1;
  s.x.resize(3 * static_cast<Eigen::Index>(points.size()));
  for (std::size_t i = 0; i < points.size(); ++i) {
    s.x.segment<3>(3 * static_cast<Eigen::Index>(i)) = points[i];
    s.sampling.table.ids.push_back(static_cast<int>(i));
    s.sampling.weights.push_back(1.0);
    s.sampling.area.push_back(1e-4);
  }
  return s;
}

ContactParams params() {
  ContactParams p;
  p.activationDistance = 0.005;
  return p;
}

/// A thin tray 0.8 × 0.8 m, 2 cm thick, its top at z = 0, moving with this velocity and angular velocity.
VolumeContactState tray(const Samples& s, const Eigen::Vector3d& velocity, const Eigen::Vector3d& angularVelocity) {
  RigidPath path;
  path.origin = {0.0, 0.0, -0.01};
  path.velocity = velocity;
  path.angularVelocity = angularVelocity;
  auto collider = std::make_shared<VolumeCollider>("tray", makeBoxShape({0.4, 0.4, 0.01}), path);
  return VolumeContactState(s.sampling, collider, params());
}

/// The largest change of the signed distance at any sample within one of `parts` equal parts of [0, h], sampled at
/// 4096 sub-times (far finer than the function's own).
double largestChangeInAPart(const VolumeContactState& state, const Samples& s, double h, int parts) {
  const int fine = 4096, length = fine / parts;
  double largest = 0.0;
  for (int i = 0; i < s.sampling.numElements(); ++i) {
    const Eigen::Vector3d p = s.x.segment<3>(3 * i);
    std::vector<double> d(fine + 1);
    for (int j = 0; j <= fine; ++j) d[j] = state.collider->query(p, h * j / fine).distance;
    for (int k = 0; k < parts; ++k) {
      const auto [lo, hi] = std::minmax_element(d.begin() + k * length, d.begin() + (k + 1) * length + 1);
      largest = std::max(largest, *hi - *lo);
    }
  }
  return largest;
}

}  // namespace

TEST_CASE("surface sweep: a tray turning or sliding under samples on its top divides nothing", "[contact]") {
  // Samples 3 mm above the top, within 0.3 m of the axis. Turning at 3 rad/s for 1/60 s, the tray's corners move
  // 2.8 cm, and sliding at 1 m/s all of it moves 1.7 cm: both far more than 5 mm, half its thinnest half-width.
  const Samples s = samplesAt({{0.0, 0.0, 0.003}, {0.2, 0.1, 0.003}, {-0.25, 0.2, 0.003}, {0.1, -0.3, 0.003}});
  const Eigen::VectorXd still = Eigen::VectorXd::Zero(s.x.size());
  const double h = 1.0 / 60.0, allowed = 0.005;
  const VolumeContactState turning = tray(s, Eigen::Vector3d::Zero(), {0.0, 0.0, 3.0});
  CHECK(turning.solidTravel(s.x, still, 0.0, h) > 2.0 * allowed);
  CHECK(surfaceSweepParts(turning, s.x, still, 0.0, h, allowed, 256.0) == 1.0);
  const VolumeContactState sliding = tray(s, {1.0, 0.0, 0.0}, Eigen::Vector3d::Zero());
  CHECK(sliding.solidTravel(s.x, still, 0.0, h) == Approx(h));
  CHECK(surfaceSweepParts(sliding, s.x, still, 0.0, h, allowed, 256.0) == 1.0);
  // Not moving at all, or moving for no time: nothing to divide.
  const VolumeContactState held = tray(s, Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero());
  CHECK(surfaceSweepParts(held, s.x, still, 0.0, h, allowed, 256.0) == 1.0);
  CHECK(surfaceSweepParts(turning, s.x, still, 0.0, 0.0, allowed, 256.0) == 1.0);
  CHECK_THROWS_AS(surfaceSweepParts(turning, s.x, still, 0.0, h, 0.0, 256.0), InputError);
  CHECK_THROWS_AS(surfaceSweepParts(turning, s.x, still, 0.0, h, std::nan(""), 256.0), InputError);
}

TEST_CASE("surface sweep: corners sweeping past a sample and a face coming at it divide the step", "[contact]") {
  const double h = 1.0 / 60.0, allowed = 0.005;
  // Beside the turning tray, level with it, just beyond its corners' reach (0.566 m from the axis). At 30 rad/s the
  // tray turns half a radian in the step, and a corner turns towards each sample: from 18 cm to about 4 cm away.
  const Samples beside = samplesAt({{0.58, 0.0, -0.01}, {0.0, -0.575, -0.01}});
  const Eigen::VectorXd still = Eigen::VectorXd::Zero(beside.x.size());
  const VolumeContactState fast = tray(beside, Eigen::Vector3d::Zero(), {0.0, 0.0, 30.0});
  const double parts = surfaceSweepParts(fast, beside.x, still, 0.0, h, allowed, 4096.0);
  CHECK(parts > 1.0);
  CHECK(parts == std::exp2(std::round(std::log2(parts))));  // a power of two
  // What the division promises, checked far more finely than it was computed.
  CHECK(largestChangeInAPart(fast, beside, h, static_cast<int>(parts)) <= allowed);
  // The bound on the material's move asks for at least as many.
  CHECK(fast.solidTravel(beside.x, still, 0.0, h) / allowed > parts / 2.0);
  // A tray rising at 3 m/s into samples 2 cm above it: the distance falls by 5 cm, as its material moves.
  const Samples above = samplesAt({{0.0, 0.0, 0.02}, {0.3, 0.3, 0.02}});
  const Eigen::VectorXd stillAbove = Eigen::VectorXd::Zero(above.x.size());
  const VolumeContactState rising = tray(above, {0.0, 0.0, 3.0}, Eigen::Vector3d::Zero());
  const double risingParts = surfaceSweepParts(rising, above.x, stillAbove, 0.0, h, allowed, 4096.0);
  CHECK(risingParts == 16.0);  // 0.05 / 0.005 = 10 asks for 16 parts: each 3.1 mm
  CHECK(largestChangeInAPart(rising, above, h, 16) <= allowed);
  CHECK(largestChangeInAPart(rising, above, h, 8) > allowed);
  // Too many sub-times needed to tell: +∞, and the caller keeps the material's bound.
  CHECK(surfaceSweepParts(rising, above.x, stillAbove, 0.0, h, allowed, 16.0) ==
        std::numeric_limits<double>::infinity());
}

TEST_CASE("surface sweep: a tray that turns a whole turn within the step travels its circumference, not 0",
          "[contact]") {
  // At 2π / h rad/s the tray ends the step where it began: the chord from start to end is zero, and its corners
  // sweep 2 m past the samples on its top. Measured before: a travel of 0 m, so the step ran whole.
  const Samples s = samplesAt({{0.0, 0.0, 0.003}, {0.2, 0.1, 0.003}, {-0.25, 0.2, 0.003}, {0.1, -0.3, 0.003}});
  const Eigen::VectorXd still = Eigen::VectorXd::Zero(s.x.size());
  const double h = 1.0 / 60.0;
  const double rate = 2.0 * 3.14159265358979323846 / h;
  const VolumeContactState whole = tray(s, Eigen::Vector3d::Zero(), {0.0, 0.0, rate});
  // The farthest sample from the axis (|(−0.25, 0.2)| = 0.32 m) travels 2π × 0.32 m.
  CHECK(whole.solidTravel(s.x, still, 0.0, h) == Approx(rate * h * std::hypot(0.25, 0.2)).epsilon(1e-9));
  // Half a turn, with a slide: the path's length, |v| h plus the arc.
  const VolumeContactState half = tray(s, {0.5, 0.0, 0.0}, {0.0, 0.0, 0.5 * rate});
  CHECK(half.solidTravel(s.x, still, 0.0, h) >= 0.5 * h + 0.5 * rate * h * std::hypot(0.25, 0.2) * (1 - 1e-9));
}
