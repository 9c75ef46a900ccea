// Contact terms at the configurations the generic checks rarely hit: just either side of the ramp's kinks
// (p = 0, p = δ), at zero slip and either side of the slip regularization ε_v; plus the stiffness parameter.
#include "energies/contact/point_cloud_contact.h"
#include "energies/contact/volume_contact.h"
#include "tests/test_util.h"

#include <catch2/catch.hpp>

#include <cstdlib>
#include <limits>
#include <set>
#include <utility>

using namespace jetshell;
using namespace jetshell::test;

namespace {

/// Points on a line of single-vertex samples, each with its own height above the plane z = 0.
struct PlaneCase {
  TriMesh mesh;  // no faces: the sampling is built by hand
  ContactSampling sampling;
  ContactParams params;
};

PlaneCase heights(const std::vector<double>& z) {
  PlaneCase c;
  c.mesh.V.resize(static_cast<Eigen::Index>(z.size()), 3);
  c.sampling.table.width = 1;
  for (std::size_t i = 0; i < z.size(); ++i) {
    c.mesh.V.row(static_cast<Eigen::Index>(i)) << 0.1 * static_cast<double>(i), 0.05, z[i];
    c.sampling.table.ids.push_back(static_cast<int>(i));
    c.sampling.weights.push_back(1.0);
    c.sampling.area.push_back(1e-3 * (1.0 + static_cast<double>(i)));
  }
  c.params.penaltyStiffness = 1e5;
  c.params.activationDistance = 0.005;
  c.params.smoothingDistance = 0.001;
  c.params.huntCrossleyDamping = 0.5;
  c.params.frictionCoefficient = 0.5;
  c.params.frictionSlipVelocity = 0.01;
  return c;
}

VolumeColliderPtr floorPlane() { return std::make_shared<VolumeCollider>("floor", makePlaneShape(), RigidPath{}); }

void requireAccurate(EnergyTerm& term, const Eigen::VectorXd& x, double initialStep = 1e-4) {
  DerivativeCheckOptions o;
  o.initialStep = initialStep;
  o.lengthScale = 0.01;
  const DerivativeCheckResult r = checkDerivatives(term, x, o);
  for (const std::string& f : checkFailures(r, DerivativeTolerances{})) FAIL_CHECK(f);
  CHECK(r.finite);
}

}  // namespace

TEST_CASE("contact terms: exact derivatives just either side of the ramp's kinks", "[contact]") {
  const double eps = 0.005, delta = 0.001;
  // Penetrations p = ε − z: just outside, just past onset, either side of δ, deep.
  const std::vector<double> p = {-1e-3 * delta, 1e-3 * delta, delta * (1 - 1e-3), delta * (1 + 1e-3), 4 * delta};
  std::vector<double> z;
  for (double v : p) z.push_back(eps - v);
  PlaneCase c = heights(z);
  VolumeContactTerms t = makeVolumeContactTerms(c.sampling, c.mesh.numVertices(), floorPlane(), c.params);
  const Eigen::VectorXd x = flatten(c.mesh.V);
  requireAccurate(*t.penalty, x, 1e-6);
  // The damping potential after a step begun a little higher (the shell approaches).
  Eigen::VectorXd start = x;
  for (int i = 0; i < c.mesh.numVertices(); ++i) start[3 * i + 2] += 2e-4;
  t.state->beginStep(start, 0.0, 0.01);
  requireAccurate(*t.damping, x, 1e-6);
  // Energies match the closed form at the deepest point: A k R(p) with R = p²/2 − δp/2 + δ²/6.
  const double pd = 4 * delta, A = c.sampling.area[4];
  Eigen::VectorXd only = x;
  for (int i = 0; i < 4; ++i) only[3 * i + 2] = 1.0;  // lift the others away
  t.state->beginStep(only, 0.0, 0.01);
  CHECK(t.penalty->evaluate(only, {}, {}) == Approx(A * 1e5 * (pd * pd / 2 - delta * pd / 2 + delta * delta / 6)));
}

TEST_CASE("contact terms: friction is differentiable at zero slip and either side of the regularization",
          "[contact]") {
  PlaneCase c = heights({0.004, 0.004, 0.004, 0.004});  // all in contact (p = 1 mm)
  VolumeContactTerms t = makeVolumeContactTerms(c.sampling, c.mesh.numVertices(), floorPlane(), c.params);
  const Eigen::VectorXd start = flatten(c.mesh.V);
  const double h = 0.01, epsV = c.params.frictionSlipVelocity * h;
  t.state->beginStep(start, 0.0, h);
  Eigen::VectorXd x = start;
  // Slips: none (only a normal move), tiny, either side of ε_v.
  const double slip[4] = {0.0, 1e-3 * epsV, epsV * (1 - 1e-3), epsV * (1 + 1e-3)};
  for (int i = 0; i < 4; ++i) {
    x[3 * i + 0] += slip[i];
    x[3 * i + 2] -= 1e-5;
  }
  requireAccurate(*t.friction, x, 1e-6);
  // At zero slip the friction force is zero (sticking starts from rest), beyond ε_v it is μλ.
  Eigen::VectorXd g = Eigen::VectorXd::Zero(x.size());
  t.friction->evaluate(x, {&g, nullptr, -1}, {});
  CHECK(g.segment<3>(0).norm() == 0.0);
  const double lambda = c.sampling.area[3] * c.params.penaltyStiffness * 0.5 * 1e-3;  // p = δ: r = δ/2
  CHECK(g[9] == Approx(c.params.frictionCoefficient * lambda).epsilon(1e-9));
}

TEST_CASE("contact terms: the penalty stiffness is a differentiable parameter", "[contact]") {
  PlaneCase c = heights({0.0045, 0.003, 0.001});
  VolumeContactTerms t = makeVolumeContactTerms(c.sampling, c.mesh.numVertices(), floorPlane(), c.params);
  EnergyTerm& term = *t.penalty;
  REQUIRE(term.parameterNames() == std::vector<std::string>{"penaltyStiffness"});
  const Eigen::VectorXd x = flatten(c.mesh.V);
  ParameterDerivatives d;
  term.evaluateParameterDerivatives(x, d);
  Eigen::VectorXd g0 = Eigen::VectorXd::Zero(x.size()), g1 = g0;
  const double k = term.parameterValues()[0], dk = 1e-3 * k;
  const double e0 = term.evaluate(x, {&g0, nullptr, -1}, {});
  term.setParameterValues({k + dk});
  const double e1 = term.evaluate(x, {&g1, nullptr, -1}, {});
  term.setParameterValues({k});
  CHECK(d.energy[0] == Approx((e1 - e0) / dk).epsilon(1e-9));
  CHECK((d.mixed.col(0) - (g1 - g0) / dk).norm() <= 1e-9 * d.mixed.norm());
  CHECK(term.parameterValues()[0] == k);
  CHECK_THROWS_AS(term.setParameterValues({-1.0}), InputError);
}

namespace {

/// Two points `gap` apart along x.
Positions twoPoints(double gap) {
  Positions rest(2, 3);
  rest << 0, 0, 0, gap, 0, 0;
  return rest;
}

/// A point cloud of two one-point actors (radius 1 cm) at `rest`.
PointCloudTerms twoPointCloud(const Positions& rest) {
  PointCloudActor a, b;
  a.vertices = {0};
  b.vertices = {1};
  a.area = b.area = {1e-4};
  a.collider.radius = b.collider.radius = 0.01;
  return makePointCloudTerms({a, b}, rest);
}

}  // namespace

TEST_CASE("contact terms: the point-cloud pair list follows the points and bumps the stencil version",
          "[contact]") {
  // Two points of different actors approaching along x.
  const Positions rest = twoPoints(0.1);
  PointCloudTerms t = twoPointCloud(rest);
  Eigen::VectorXd x = flatten(rest);
  t.penalty->updateStencils(x);
  CHECK(t.penalty->stencils().size() == 0);  // 10 cm apart: not even a candidate
  const std::uint64_t v0 = t.penalty->stencilVersion();
  x[3] = 0.015;  // 1.5 cm apart: inside 2r = 2 cm
  t.penalty->updateStencils(x);
  CHECK(t.penalty->stencilVersion() != v0);
  REQUIRE(t.penalty->stencils().size() == 1);
  Eigen::VectorXd g = Eigen::VectorXd::Zero(6);
  CHECK(t.penalty->evaluate(x, {&g, nullptr, -1}, {}) > 0.0);
  CHECK(g[0] > 0.0);  // pushes point 0 towards −x, away from point 1
  CHECK(g[3] < 0.0);
  CHECK(t.state->minDistanceRatio(x) == Approx(0.75));
  requireAccurate(*t.penalty, x, 1e-4);
}

TEST_CASE("contact terms: positions the broad phase cannot hash give the point-cloud penalty an infinite energy",
          "[contact]") {
  // A line search's trial of a wild step (a floppy static scene's first Newton step): the broad phase refused it
  // with an input error that ended the run ("a point-cloud radius too small for the scene's size").
  const Positions rest = twoPoints(0.015);
  PointCloudTerms t = twoPointCloud(rest);
  const Eigen::VectorXd x = flatten(rest);
  const double e = t.penalty->evaluate(x, {}, {});
  REQUIRE(e > 0.0);
  for (double wild : {std::numeric_limits<double>::quiet_NaN(), 1e300, 1e20}) {
    Eigen::VectorXd y = x;
    y[4] = wild;
    t.penalty->updateStencils(y);
    CHECK(t.state->unhashable());
    CHECK(t.penalty->evaluate(y, {}, {}) == std::numeric_limits<double>::infinity());
  }
  // Back at hashable positions, the same pairs and energy.
  t.penalty->updateStencils(x);
  CHECK_FALSE(t.state->unhashable());
  CHECK(t.penalty->evaluate(x, {}, {}) == e);
}

TEST_CASE("contact terms: the point-cloud candidate list survives a common translation and never misses a pair",
          "[contact]") {
  // A 6 × 6 grid of samples 1.5 cm apart in two actors (alternate rows), radius 1 cm: contact distance 2 cm.
  constexpr int n = 6;
  Positions rest(n * n, 3);
  PointCloudActor a, b;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      const int v = i * n + j;
      rest.row(v) << 0.015 * i, 0.015 * j, 0.0;
      PointCloudActor& actor = i % 2 == 0 ? a : b;
      actor.vertices.push_back(v);
      actor.area.push_back(1e-4);
    }
  a.collider.radius = b.collider.radius = 0.01;
  PointCloudTerms t = makePointCloudTerms({a, b}, rest);
  Eigen::VectorXd x = flatten(rest);
  t.state->refresh(x);
  const int built = t.state->rebuilds();

  // The whole cloud falls 30 cm: no pair distance changes, so the list is kept.
  for (int v = 0; v < n * n; ++v) x[3 * v + 2] -= 0.3;
  CHECK_FALSE(t.state->refresh(x));
  CHECK(t.state->rebuilds() == built);

  // Random relative motions, a few millimetres each time: whenever the list is kept or rebuilt, every pair of
  // different actors closer than 2 cm is among the candidates.
  std::srand(7);
  for (int trial = 0; trial < 40; ++trial) {
    for (int k = 0; k < x.size(); ++k) x[k] += 0.004 * (std::rand() / static_cast<double>(RAND_MAX) - 0.5);
    t.state->refresh(x);
    std::set<std::pair<int, int>> listed;
    const StencilTable& c = t.state->candidates();
    for (int e = 0; e < c.size(); ++e)
      listed.insert({std::min(c.ids[2 * e], c.ids[2 * e + 1]), std::max(c.ids[2 * e], c.ids[2 * e + 1])});
    for (int p = 0; p < n * n; ++p)
      for (int q = p + 1; q < n * n; ++q) {
        if ((p / n) % 2 == (q / n) % 2) continue;  // same actor, no self-contact
        if ((x.segment<3>(3 * p) - x.segment<3>(3 * q)).norm() < 0.02) CHECK(listed.count({p, q}) == 1);
      }
  }
  CHECK(t.state->rebuilds() > built);  // the relative motions did force rebuilds
}

TEST_CASE("contact terms: a moving solid's travel over a step counts at the samples it can reach", "[contact]") {
  // Samples at (0, 0.05, 0) and (0.1, 0.05, −0.1), both 5 cm from a ball of radius 5 cm centred at (0, 0.05, −0.1)
  // and from a cube of the same half width there.
  const PlaneCase c = heights({0.0, -0.1});
  const Eigen::VectorXd x = flatten(c.mesh.V), still = Eigen::VectorXd::Zero(x.size());
  auto solid = [](VolumeShapePtr shape, const Eigen::Vector3d& velocity, const Eigen::Vector3d& angularVelocity) {
    RigidPath path;
    path.origin = {0.0, 0.05, -0.1};
    path.velocity = velocity;
    path.angularVelocity = angularVelocity;
    return std::make_shared<VolumeCollider>("solid", shape, path);
  };
  auto ball = [&](const Eigen::Vector3d& velocity, const Eigen::Vector3d& angularVelocity) {
    return solid(makeSphereShape(0.05), velocity, angularVelocity);
  };
  const VolumeContactState fixed(c.sampling, ball({0.0, 0.0, 0.0}, {0.0, 0.0, 0.0}), c.params);
  CHECK(fixed.solidTravel(x, still, 0.0, 1.0) == 0.0);
  // Rising at 2 m/s: 2 cm in 10 ms cannot reach a sample 5 cm away (activation 5 mm), 10 cm in 50 ms can; nor
  // can 2 cm, unless the sample comes 3 cm towards it.
  const VolumeContactState rising(c.sampling, ball({0.0, 0.0, 2.0}, {0.0, 0.0, 0.0}), c.params);
  CHECK(rising.solidTravel(x, still, 0.0, 0.01) == 0.0);
  CHECK(rising.solidTravel(x, still, 0.0, 0.05) == Approx(0.1));
  Eigen::VectorXd falling = still;
  falling[2] = -3.0;
  CHECK(rising.solidTravel(x, falling, 0.0, 0.01) == Approx(0.02));
  // The cube turning at 10 rad/s about z for 0.1 s: the sample on the axis does not move, the other 10 cm off
  // it travels the arc 0.1 · 1 rad (its chord, 2 · 0.1 · sin(0.5), would miss what a longer turn sweeps). The
  // ball turning so stays in place, and so does a capsule turning about its own axis (local z); about another
  // axis it sweeps.
  const VolumeContactState cube(c.sampling, solid(makeBoxShape({0.05, 0.05, 0.05}), {0, 0, 0}, {0, 0, 10.0}), c.params);
  CHECK(cube.solidTravel(x, still, 0.0, 0.1) == Approx(0.1 * 1.0));
  const VolumeContactState spinningBall(c.sampling, ball({0.0, 0.0, 0.0}, {3.0, -4.0, 10.0}), c.params);
  CHECK(spinningBall.solidTravel(x, still, 0.0, 0.1) == 0.0);
  const VolumeContactState rolling(c.sampling, solid(makeCapsuleShape(0.05, 0.0), {0, 0, 0}, {0, 0, 10.0}), c.params);
  CHECK(rolling.solidTravel(x, still, 0.0, 0.1) == 0.0);
  const VolumeContactState tumbling(c.sampling, solid(makeCapsuleShape(0.05, 0.0), {0, 0, 0}, {0, 10.0, 0}), c.params);
  CHECK(tumbling.solidTravel(x, still, 0.0, 0.1) == Approx(0.1 * 1.0));
  // Later the centre has moved with the path: 1 s at 2 m/s leaves the ball 2 m above both samples.
  CHECK(rising.solidTravel(x, still, 1.0, 0.01) == 0.0);
}

TEST_CASE("contact terms: friction slips against the solid's own move over the step, a turn's chord and a stop",
          "[contact]") {
  // Samples 1 mm into the activation band of a floor that moves along its own surface. A sample carried exactly as
  // the floor's material moves over the step feels no friction; one left behind by more than ε_v feels all of it.
  PlaneCase c = heights({0.004, 0.004, 0.004, 0.004});
  const Eigen::VectorXd start = flatten(c.mesh.V);
  const double h = 0.01;
  const double lambda = c.sampling.area[3] * c.params.penaltyStiffness * 0.5 * 1e-3;  // p = δ: r = δ/2
  auto friction = [&](const RigidPath& path, const Eigen::VectorXd& x) {
    VolumeContactTerms t = makeVolumeContactTerms(c.sampling, c.mesh.numVertices(),
                                                  std::make_shared<VolumeCollider>("floor", makePlaneShape(), path),
                                                  c.params);
    t.state->beginStep(start, 0.0, h);
    Eigen::VectorXd g = Eigen::VectorXd::Zero(x.size());
    t.friction->evaluate(x, {&g, nullptr, -1}, {});
    return g;
  };
  // A turntable at 30 rad/s: 0.3 rad a step, so the chord and the tangent h·v part by 4.5% of the radius (1.3 cm
  // at the last sample, 0.3 m out), a hundred times ε_v = 0.1 mm.
  RigidPath turntable;
  turntable.angularVelocity = {0.0, 0.0, 30.0};
  const Eigen::Matrix3d turn = Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  Eigen::VectorXd carried = start, tangent = start;
  for (int i = 0; i < 4; ++i) {
    const Eigen::Vector3d p = start.segment<3>(3 * i);
    carried.segment<3>(3 * i) = turn * p;
    tangent.segment<3>(3 * i) = p + h * Eigen::Vector3d(0.0, 0.0, 30.0).cross(p);
  }
  CHECK(friction(turntable, carried).norm() < 1e-9 * lambda);
  CHECK(friction(turntable, tangent).segment<3>(9).norm() == Approx(c.params.frictionCoefficient * lambda));
  // A conveyor keyframed to move 1 mm along x by t = h/2 and stop: the floor moves 1 mm over the step, not the
  // 2 mm its velocity at the step's start would give.
  RigidPath conveyor;
  conveyor.keyframes = {{0.5 * h, {0.001, 0.0, 0.0}, Eigen::Quaterniond::Identity()}};
  Eigen::VectorXd moved = start;
  for (int i = 0; i < 4; ++i) moved[3 * i] += 0.001;
  CHECK(friction(conveyor, moved).norm() < 1e-9 * lambda);
  for (int i = 0; i < 4; ++i) moved[3 * i] += 0.001;
  CHECK(friction(conveyor, moved).segment<3>(9).norm() == Approx(c.params.frictionCoefficient * lambda));
}
