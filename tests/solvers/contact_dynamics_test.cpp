// Shells meeting rigid volume actors and each other, through the solver (ShellSystem + DynamicsSolver):
// friction on an incline, a cloth draped on a sphere and sliding off a box, two cloths dropped on each other,
// a problem without colliders that builds no contact at all, the Newton correction test on contact steps, and
// steps divided for a fast moving solid.
// Small meshes, a few hundred steps at most.
#include "core/mesh_generators.h"
#include "solvers/dynamics.h"
#include "solvers/shell_system.h"
#include "solvers/step_error_check.h"
#include "solvers/time_step_policy.h"
#include "test_problems.h"

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <utility>

using namespace jetshell;

namespace {

ShellMaterialParams cloth() {
  // E = 1e5 Pa, ν = 0.25, ρ0 = 1000 kg/m³, h = 2 mm (the T-shirt's material).
  return ShellMaterialParamsFrom3dIsotropic(1e5, 0.25, 1000.0, 0.002);
}

/// A square cloth of side `size`, n × n cells, horizontal (y up) with its centre at `centre`.
TriMesh square(double size, int n, const Eigen::Vector3d& centre) {
  TriMesh m = makeRectangleGrid(size, size, n, n);
  Positions V(m.V.rows(), 3);
  for (Eigen::Index v = 0; v < m.V.rows(); ++v)
    V.row(v) << centre.x() + m.V(v, 0) - 0.5 * size, centre.y(), centre.z() - (m.V(v, 1) - 0.5 * size);
  m.V = V;
  return m;
}

VolumeColliderPart collider(const std::string& name, VolumeShapePtr shape, const Eigen::Vector3d& origin,
                            const Eigen::Quaterniond& rotation = Eigen::Quaterniond::Identity(),
                            double mu = 0.5) {
  RigidPath path;
  path.origin = origin;
  path.rotation = rotation;
  ContactParams c;
  c.frictionCoefficient = mu;
  return {std::make_shared<VolumeCollider>(name, shape, path), c};
}

DynamicsOptions options(int iterations = 30) {
  DynamicsOptions o;
  o.timeStep = 1.0 / 60.0;
  o.newton.maxIterations = iterations;
  o.newton.residualTolerance = 1e-5;
  return o;
}

/// A 0.6 m square cloth (12 × 12 cells) 3 cm above a ball of radius 0.15 m resting on the floor.
ShellProblem clothOverBall() {
  ShellProblem p;
  p.mesh = square(0.6, 12, {0.0, 0.33, 0.0});
  p.material = cloth();
  p.material.massDampingCoefficient = 2.0;
  p.volumes = {collider("ball", makeSphereShape(0.15), Eigen::Vector3d(0, 0.15, 0)),
               collider("floor", makePlaneShape(), Eigen::Vector3d::Zero(),
                        Eigen::Quaterniond::FromTwoVectors(Eigen::Vector3d::UnitZ(), Eigen::Vector3d::UnitY()))};
  return p;
}

/// Cloth lying on a 0.8 m square tray 2 cm thick (top at y = 0) turning at 3 rad/s about y, friction 0.5.
ShellProblem onTurntable(TriMesh sheet) {
  ShellProblem p;
  p.mesh = std::move(sheet);
  p.material = cloth();
  RigidPath path;
  path.origin = {0.0, -0.01, 0.0};
  path.angularVelocity = {0.0, 3.0, 0.0};
  ContactParams c;
  c.frictionCoefficient = 0.5;
  p.volumes = {{std::make_shared<VolumeCollider>("tray", makeBoxShape({0.4, 0.01, 0.4}), path), c}};
  return p;
}

/// Two cloths stacked into one problem, actors "lower" and "upper" (point clouds of radius 1.5 cm), over the
/// floor.
ShellProblem twoClothsOverFloor(const TriMesh& lower, const TriMesh& upper) {
  ShellProblem p;
  const int n = lower.numVertices();
  p.mesh.V.resize(2 * n, 3);
  p.mesh.V << lower.V, upper.V;
  p.mesh.F.resize(2 * lower.numFaces(), 3);
  p.mesh.F << lower.F, (upper.F.array() + n).matrix();
  for (int a = 0; a < 2; ++a) {
    ShellActorPart part;
    part.name = a == 0 ? "lower" : "upper";
    part.mesh = a == 0 ? lower : upper;  // its own vertices, the stacked mesh's block from firstVertex
    part.firstVertex = a == 0 ? 0 : n;
    part.material = cloth();
    part.pointCloudCollider.radius = 0.015;
    p.actors.push_back(part);
  }
  p.volumes = {collider("floor", makePlaneShape(), Eigen::Vector3d::Zero(),
                        Eigen::Quaterniond::FromTwoVectors(Eigen::Vector3d::UnitZ(), Eigen::Vector3d::UnitY()))};
  return p;
}

Eigen::Vector3d meanOf(const Eigen::VectorXd& x) {
  Eigen::Vector3d s = Eigen::Vector3d::Zero();
  for (Eigen::Index v = 0; v < x.size() / 3; ++v) s += x.segment<3>(3 * v);
  return s / static_cast<double>(x.size() / 3);
}

double lowest(const Eigen::VectorXd& x) {
  double y = 1e300;
  for (Eigen::Index v = 0; v < x.size() / 3; ++v) y = std::min(y, x[3 * v + 1]);
  return y;
}

}  // namespace

TEST_CASE("contact dynamics: a problem without colliders builds no contact term and runs no detection",
          "[contact]") {
  ShellProblem p;
  p.mesh = square(0.2, 4, {0, 1, 0});
  p.material = cloth();
  ShellSystem system(p, AnalysisKind::Dynamics);
  CHECK(system.contact.empty());
  for (const std::string& name : system.objective().activeTermNames()) {
    CHECK(name.find("contact") == std::string::npos);
    CHECK(name.find("pointcloud") == std::string::npos);
  }
  const Eigen::VectorXd x = system.restPositions();
  CHECK(system.objective().stepBound(x, Eigen::VectorXd::Constant(x.size(), 100.0)) == 1.0);
  // One actor with a point-cloud collider but no self-contact has nothing to collide with either.
  ShellActorPart a;
  a.name = "cloth";
  a.mesh = p.mesh;
  a.material = p.material;
  p.actors = {a};
  ShellSystem single(p, AnalysisKind::Dynamics);
  CHECK(single.contact.empty());
}

TEST_CASE("contact dynamics: on an incline a shell sticks when tan θ < μ and slides with g(sin θ − μ cos θ) "
          "when tan θ > μ", "[contact]") {
  const double mu = 0.5, g = 9.81, eps = 0.005;
  for (double tanTheta : {0.3, 0.8}) {
    const double theta = std::atan(tanTheta);
    // The incline's normal n = (−sin θ, cos θ, 0); gravity along it points down = −(cos θ, sin θ, 0).
    const Eigen::Vector3d n(-std::sin(theta), std::cos(theta), 0.0), down(-std::cos(theta), -std::sin(theta), 0.0);
    const Eigen::Quaterniond R = Eigen::Quaterniond::FromTwoVectors(Eigen::Vector3d::UnitZ(), n);
    ShellProblem p;
    TriMesh m = square(0.1, 2, Eigen::Vector3d::Zero());
    // Lay the patch in the incline plane, inside the activation band (0.9 ε above the surface).
    const Eigen::Quaterniond tilt = Eigen::Quaterniond::FromTwoVectors(Eigen::Vector3d::UnitY(), n);
    for (Eigen::Index v = 0; v < m.V.rows(); ++v)
      m.V.row(v) = (tilt * Eigen::Vector3d(m.V.row(v)) + 0.9 * eps * n).transpose();
    p.mesh = m;
    p.material = cloth();
    p.volumes = {collider("incline", makePlaneShape(), Eigen::Vector3d::Zero(), R, mu)};
    ShellSystem system(p, AnalysisKind::Dynamics);
    DynamicsSolver solver(system, options());
    std::vector<double> speed;
    for (int s = 0; s < 36; ++s) {
      REQUIRE(solver.step().success);
      speed.push_back(meanOf(solver.velocities()).dot(down));
    }
    INFO("tan θ = " << tanTheta);
    // The force the patch puts on the incline over the last step: its penalty's push and friction's drag.
    const auto forces = system.contact.solidForces(solver.positions(), solver.time());
    REQUIRE(forces.size() == 1);
    const Eigen::Vector3d force = forces[0].second;
    const double weight = 2.0 * 0.01 * g;  // 2 kg/m² over 0.1 m × 0.1 m
    CAPTURE(force.transpose());
    CHECK(-force.dot(n) == Approx(weight * std::cos(theta)).epsilon(0.03));
    if (tanTheta < mu) {
      // Regularized Coulomb friction creeps below the slip velocity V_f = 0.01 m/s, never slides.
      CHECK(std::abs(speed.back()) < 0.01);
      CHECK((meanOf(solver.positions()) - meanOf(system.restPositions())).dot(down) < 0.005);
      // Resting, it weighs on the incline with its whole weight: friction holds what the normal force does not.
      CHECK((force - Eigen::Vector3d(0.0, -weight, 0.0)).norm() < 0.03 * weight);
    } else {
      const double expected = g * (std::sin(theta) - mu * std::cos(theta));
      const double measured = (speed[35] - speed[11]) / (24.0 / 60.0);  // after the landing transient
      CHECK(measured == Approx(expected).epsilon(0.02));
      // Sliding, friction drags the incline down the slope with μ times the normal force.
      CHECK(force.dot(down) == Approx(mu * weight * std::cos(theta)).epsilon(0.03));
    }
    CHECK(solver.positions().allFinite());
  }
}

TEST_CASE("contact dynamics: a square cloth dropped on a sphere drapes over it", "[contact]") {
  const ShellProblem p = clothOverBall();
  ShellSystem system(p, AnalysisKind::Dynamics);
  DynamicsSolver solver(system, options());
  for (int s = 0; s < 45; ++s) REQUIRE(solver.step().success);
  const Eigen::VectorXd& x = solver.positions();
  REQUIRE(x.allFinite());
  // The centre rests on the ball's top (y ≈ 0.3 + ε), the corners hang well below it.
  const int centre = 6 * 13 + 6;
  CHECK(x[3 * centre + 1] == Approx(0.305).margin(0.01));
  CHECK(x[1] < 0.2);
  // Nothing inside the ball beyond the penalty's tolerance (1 mm).
  for (const VolumeContactTerms& v : system.contact.volume) CHECK(v.state->minDistance(x) > -0.001);
}

TEST_CASE("contact dynamics: a cloth falling at 6 m/s does not pass through a small ball", "[contact]") {
  // A step at 60 Hz moves the cloth 10 cm, more than the ball's diameter (6 cm): without a step bound for the
  // ball the start of a step lands the centre past the ball's middle, and the penalty pushes it out below.
  ShellProblem p;
  p.mesh = square(0.3, 8, {0.0, 0.05, 0.0});
  p.material = cloth();
  p.volumes = {collider("ball", makeSphereShape(0.03), Eigen::Vector3d::Zero())};
  ShellSystem system(p, AnalysisKind::Dynamics);
  DynamicsOptions o = options();
  o.acceptIterationCap = true;
  DynamicsSolver solver(system, o);
  Eigen::VectorXd v = Eigen::VectorXd::Zero(solver.positions().size());
  for (Eigen::Index i = 1; i < v.size(); i += 3) v[i] = -6.0;
  solver.setState(solver.positions(), v, 0.0);
  for (int s = 0; s < 6; ++s) REQUIRE(solver.step().success);
  const Eigen::VectorXd& x = solver.positions();
  REQUIRE(x.allFinite());
  const int centre = 4 * 9 + 4;
  CHECK(x[3 * centre + 1] > 0.02);  // held on top of the ball (its top at y = 0.03), not below it
  CHECK(system.contact.volume[0].state->minDistance(x) > -0.005);
}

/// A 0.3 m cloth (8 × 8 cells) at rest at height y = 0.05, and a capsule of radius 2 cm (axis along y, 2 cm
/// half length) whose top starts 5 cm below the cloth and rises at `speed` m/s.
ShellProblem clothOverRisingCapsule(double speed) {
  ShellProblem p;
  p.mesh = square(0.3, 8, {0.0, 0.05, 0.0});
  p.material = cloth();
  RigidPath path;
  path.origin = {0.0, -0.04, 0.0};
  path.rotation = Eigen::Quaterniond::FromTwoVectors(Eigen::Vector3d::UnitZ(), Eigen::Vector3d::UnitY());
  path.velocity = {0.0, speed, 0.0};
  p.volumes = {{std::make_shared<VolumeCollider>("bullet", makeCapsuleShape(0.02, 0.02), path), ContactParams{}}};
  return p;
}

TEST_CASE("contact dynamics: a solid rising at 12 m/s through a cloth carries it instead of passing through",
          "[contact]") {
  // At 60 Hz the capsule rises 20 cm a step, five times its height: seen only where each step ends, it would be
  // below the cloth at one step's end and above it at the next. The step is divided so that it moves at most
  // half its thinnest half-width (1 cm) per part: 32 parts.
  ShellProblem p = clothOverRisingCapsule(12.0);
  ShellSystem system(p, AnalysisKind::Dynamics);
  DynamicsOptions o = options();
  o.acceptIterationCap = true;
  DynamicsSolver solver(system, o);
  const ShellContact::SolidSweep sweep =
      system.contact.solidSweep(solver.positions(), solver.velocities(), 0.0, o.timeStep);
  CHECK(sweep.solid == "bullet");
  CHECK(sweep.travel == Approx(0.2));
  CHECK(sweep.allowed == Approx(0.01));
  const int centre = 4 * 9 + 4;
  double highest = -1.0;
  for (int s = 0; s < 3; ++s) {
    const StepReport r = solver.step();
    REQUIRE(r.success);
    CHECK(r.parts >= 16);
    REQUIRE(solver.positions().allFinite());
    highest = std::max(highest, solver.positions()[3 * centre + 1]);
  }
  // Three steps take the capsule's top from y = 0 to 0.6 m: the cloth's centre went up with it.
  CHECK(highest > 0.3);
}

TEST_CASE("contact dynamics: a step a moving solid would need more than 2^maxCuts parts for fails, naming it",
          "[contact]") {
  ShellProblem p = clothOverRisingCapsule(300.0);  // 5 m a step against 1 cm a part
  ShellSystem system(p, AnalysisKind::Dynamics);
  DynamicsSolver solver(system, options());
  const Eigen::VectorXd before = solver.positions();
  const StepReport r = solver.step();
  CHECK_FALSE(r.success);
  CHECK(r.newtonIterations == 0);
  CHECK(solver.positions() == before);
  CHECK(solver.time() == 0.0);
  CHECK_THAT(r.message, Catch::Contains("the solid 'bullet' moves 5 m near the shell") &&
                            Catch::Contains("more than 64 parts") && Catch::Contains("take a time step of at most"));
}

TEST_CASE("contact dynamics: a static or distant solid divides no step", "[contact]") {
  ShellProblem p = clothOverRisingCapsule(12.0);
  ShellSystem system(p, AnalysisKind::Dynamics);
  const Eigen::VectorXd x = system.restPositions(), v = Eigen::VectorXd::Zero(x.size());
  // 1 ms: the capsule rises 1.2 cm, and its top is 5 cm below the cloth.
  CHECK(system.contact.solidSweep(x, v, 0.0, 1e-3).parts == 1.0);
  ShellProblem still = clothOverRisingCapsule(0.0);
  ShellSystem stillSystem(still, AnalysisKind::Dynamics);
  CHECK(stillSystem.contact.solidSweep(x, v, 0.0, 1.0).parts == 1.0);
}

TEST_CASE("contact dynamics: a cloth on a turning tray is carried round in steps its surface does not divide",
          "[contact]") {
  // A 0.8 m square tray 2 cm thick (top at y = 0) turning at 3 rad/s about y, a 0.4 m cloth lying on its middle.
  // Under the cloth's corners its material moves 1.4 cm a step, more than twice half its thinnest half-width
  // (5 mm), so the bound on its material's move asks for 4 parts a step; the signed distance under the cloth does
  // not change at all.
  const ShellProblem p = onTurntable(square(0.4, 8, {0.0, 0.004, 0.0}));
  ShellSystem system(p, AnalysisKind::Dynamics);
  DynamicsOptions o = options();
  DynamicsSolver solver(system, o);
  const ShellContact::SolidSweep sweep =
      system.contact.solidSweep(solver.positions(), solver.velocities(), 0.0, o.timeStep);
  CHECK(sweep.parts == 1.0);
  CHECK(sweep.bySurface);
  CHECK(sweep.travel > 2.0 * sweep.allowed);
  const int corner = 0;
  const Eigen::Vector3d start = solver.positions().segment<3>(3 * corner);
  for (int s = 0; s < 30; ++s) {
    const StepReport r = solver.step();
    REQUIRE(r.success);
    CHECK(r.parts == 1);
    REQUIRE(solver.positions().allFinite());
  }
  // Friction carried the cloth round (the tray turned 1.5 rad in 0.5 s) and kept it on the tray's top.
  const Eigen::Vector3d end = solver.positions().segment<3>(3 * corner);
  const double turned =
      std::atan2(start.z() * end.x() - start.x() * end.z(), start.x() * end.x() + start.z() * end.z());
  CHECK(turned > 0.5);
  CHECK(end.y() > 0.0);
  CHECK(end.y() < 0.01);
}

TEST_CASE("contact dynamics: a patch friction carries round a turntable keeps its radius", "[contact]") {
  // A 5 cm patch lying 0.25 m off the axis of a tray turning at 3 rad/s: ω² r = 2.25 m/s², well below μ g =
  // 4.9 m/s², so friction holds it on its circle. Friction's slip is measured against the tray's own move over
  // each step, the chord of its turn (0.05 rad a step); against the tangent h·v, which ends 0.3 mm outside the
  // circle each step (r θ²/2, twice ε_v), the patch was pushed outwards, by 20% of its radius in 2 s. What drift
  // is left (2%) is the creep regularized friction allows: slips slower than V_f = 1 cm/s count as sticking.
  const ShellProblem p = onTurntable(square(0.05, 5, {0.25, 0.002, 0.0}));
  ShellSystem system(p, AnalysisKind::Dynamics);
  DynamicsSolver solver(system, options());
  for (int s = 0; s < 120; ++s) REQUIRE(solver.step().success);
  const Eigen::Vector3d centre = meanOf(solver.positions());
  const double radius = std::hypot(centre.x(), centre.z());
  CHECK(radius > 0.24);
  CHECK(radius < 0.26);
  // It went round with the tray (6 rad in 2 s), less the little it lagged while settling.
  const double turned = std::atan2(-centre.z(), centre.x());  // about +y: x → −z
  CHECK(std::remainder(turned - 6.0, 2.0 * std::acos(-1.0)) > -0.3);
}

TEST_CASE("contact dynamics: a box lifted by keyframes carries a cloth up, and it rests there when the box stops",
          "[contact]") {
  // A 0.6 m tray 4 cm thick (top at y = 0) rises 0.3 m in 0.3 s (1 m/s: 1.7 cm a step at 60 Hz, more than half
  // its half-thickness, so those steps are divided), then stays; the cloth lying on it goes up with it, flies on a
  // little when the tray stops, and ends resting on its top.
  ShellProblem p;
  p.mesh = square(0.4, 8, {0.0, 0.004, 0.0});
  p.material = cloth();
  p.material.massDampingCoefficient = 2.0;
  RigidPath path;
  path.origin = {0.0, -0.02, 0.0};
  path.keyframes = {{0.3, {0.0, 0.3, 0.0}, Eigen::Quaterniond::Identity()}};
  p.volumes = {{std::make_shared<VolumeCollider>("lift", makeBoxShape({0.3, 0.02, 0.3}), path), ContactParams{}}};
  ShellSystem system(p, AnalysisKind::Dynamics);
  DynamicsOptions o = options();
  o.acceptIterationCap = true;
  DynamicsSolver solver(system, o);
  int divided = 0;
  for (int s = 0; s < 60; ++s) {
    const StepReport r = solver.step();
    REQUIRE(r.success);
    if (r.parts > 1) ++divided;
    REQUIRE(solver.positions().allFinite());
  }
  // The lift's own 18 steps are divided, the resting ones are not.
  CHECK(divided >= 17);
  CHECK(divided <= 19);
  const Eigen::VectorXd& x = solver.positions();
  double lowest = 1.0, highest = -1.0;
  for (Eigen::Index v = 0; v < x.size() / 3; ++v) {
    lowest = std::min(lowest, x[3 * v + 1]);
    highest = std::max(highest, x[3 * v + 1]);
  }
  // On the top at y = 0.3, within the activation distance (5 mm), not left below or thrown off.
  CHECK(lowest > 0.29);
  CHECK(highest < 0.31);
}

TEST_CASE("contact dynamics: a cloth dropped on the edge of a box slides off it", "[contact]") {
  ShellProblem p;
  // Most of the cloth beyond the box's edge at x = 0: its weight pulls it over the edge.
  p.mesh = square(0.3, 8, {0.08, 0.22, 0.0});
  p.material = cloth();
  p.volumes = {collider("box", makeBoxShape({0.1, 0.1, 0.2}), Eigen::Vector3d(-0.1, 0.1, 0.0),
                        Eigen::Quaterniond::Identity(), 0.1)};
  ShellSystem system(p, AnalysisKind::Dynamics);
  DynamicsSolver solver(system, options());
  for (int s = 0; s < 70; ++s) REQUIRE(solver.step().success);
  const Eigen::VectorXd& x = solver.positions();
  REQUIRE(x.allFinite());
  // It has slid off: nothing rests on the box's top (y = 0.2 for x < 0) any more, most of it hangs below.
  for (Eigen::Index v = 0; v < x.size() / 3; ++v)
    if (x[3 * v] < 0.0) CHECK(x[3 * v + 1] < 0.15);
  CHECK(meanOf(x).y() < 0.1);
  CHECK(system.contact.volume[0].state->minDistance(x) > -0.001);
}

TEST_CASE("contact dynamics: two cloths dropped on each other do not interpenetrate", "[contact]") {
  // 2 cm spacing, r = 1.5 cm: the samples of a layer overlap, so the other layer cannot pass between them.
  const TriMesh lower = square(0.2, 10, {0.0, 0.012, 0.0}), upper = square(0.2, 10, {0.03, 0.07, 0.02});
  const int n = lower.numVertices();
  const ShellProblem p = twoClothsOverFloor(lower, upper);
  ShellSystem system(p, AnalysisKind::Dynamics);
  REQUIRE(system.contact.pointCloud.state);
  DynamicsSolver solver(system, options());
  double closest = 1.0;
  for (int s = 0; s < 30; ++s) {
    REQUIRE(solver.step().success);
    closest = std::min(closest, system.contact.pointCloud.state->minDistanceRatio(solver.positions()));
  }
  const Eigen::VectorXd& x = solver.positions();
  REQUIRE(x.allFinite());
  // The upper cloth rests on the lower one (its overhang droops to the floor), and no two samples of the two
  // cloths ever came closer than half the contact distance 2r.
  CHECK(closest > 0.5);
  CHECK(meanOf(x.tail(3 * n)).y() > meanOf(x.head(3 * n)).y() + 0.01);
  CHECK(lowest(x) > -0.001);
}

TEST_CASE("contact dynamics: the Newton correction ends a contact step only when no vertex moved more than a "
          "fraction of the contact ramp, and the drape's Newton error stays far below its time error",
          "[contact]") {
  testing::SingleThread single;
  const ShellProblem p = clothOverBall();
  const double kappa = 0.3, ramp = ContactParams{}.smoothingDistance, dt = 1.0 / 60.0;
  // A third of a second: the cloth lands on the ball and slides down it. Later its folds form by a bifurcation
  // that any change of the solves flips (at 0.75 s, 45 steps, the default rule's run is 7 mm from the one solved
  // tightly, and that one 21 mm from its own run at Δt/2), and no rule's error can be judged there.
  const int steps = 20;
  struct Run {
    Eigen::VectorXd x;
    int correctionStops = 0;
  };
  const auto run = [&](double fraction, double eta, int refine) {
    ShellSystem system(p, AnalysisKind::Dynamics);
    REQUIRE(system.contact.narrowestRamp == ramp);
    DynamicsOptions o = options();
    o.contactCorrectionFraction = fraction;
    o.updateTolerance = eta;
    o.timeStep = dt / refine;
    DynamicsSolver solver(system, o);
    Run r;
    for (int s = 0; s < steps * refine; ++s) {
      const StepReport report = solver.step();
      REQUIRE(report.success);
      for (const SolverSummary& summary : report.solves) {
        if (summary.iterateEstimate != "Newton correction") continue;
        ++r.correctionStops;
        // Only after a full Newton step that moved no vertex farther than κ δ, and only as a converged solve.
        CHECK(summary.converged());
        REQUIRE_FALSE(summary.trace.empty());
        CHECK(summary.trace.back().stepLength == 1.0);
        CHECK(summary.trace.back().largestMove <= kappa * ramp * (1 + 1e-12));
      }
    }
    r.x = solver.positions();
    return r;
  };
  const Run on = run(kappa, 0.1, 1), off = run(0.0, 0.1, 1);
  const Run tight = run(0.0, 0.01, 1), tightHalf = run(0.0, 0.01, 2);
  CHECK(on.correctionStops >= 1);  // measured: 8 of 20 steps (15 when the correction alone was judged)
  CHECK(off.correctionStops == 0);
  const double discretization = (tight.x - tightHalf.x).lpNorm<Eigen::Infinity>();
  const double newtonError = (on.x - tight.x).lpNorm<Eigen::Infinity>();
  INFO("discretization " << discretization << " m, Newton error " << newtonError << " m (without the rule "
                         << (off.x - tight.x).lpNorm<Eigen::Infinity>() << " m)");
  CHECK(newtonError <= 0.2 * discretization);
}

TEST_CASE("contact dynamics: the drape's passed steps end within their threshold of the same steps solved "
          "tightly (with contact terms the correction judges the error left, and Newton's contraction may refuse a "
          "residual estimate)",
          "[contact]") {
  // With contact terms the correction alone used to be judged: the T-shirt's passes ended up to 1.47 times their
  // threshold from the tightly solved step (BENCHMARKS.md, Contact, session 66), this drape's up to 3.3 times.
  // Newton's corrections there do not contract steadily, and a short one can precede long ones. Each step of the
  // drape, taken with the policy `jetshell run` uses, is solved again tightly from the same state, on from its
  // iterate (as `jetshell bench contact --newton-error` does), and held to the threshold its pass promised.
  testing::SingleThread single;
  const ShellProblem p = clothOverBall();
  ShellSystem runSystem(p, AnalysisKind::Dynamics), tightSystem(p, AnalysisKind::Dynamics);
  DynamicsOptions o;
  applyTimeStepPolicy(TimeStepPolicy::Jetshell, o);
  o.timeStep = 1.0 / 60.0;
  DynamicsSolver run(runSystem, o), tight(tightSystem, tightStepOptions(o));
  int corrections = 0, residualPasses = 0;
  double worstCorrection = 0.0, worstResidual = 0.0;
  for (int step = 0; step < 60; ++step) {
    const DynamicsSolver::Snapshot start = run.snapshot();
    const StepReport taken = run.step();
    INFO("step " << step << ": " << taken.message);
    REQUIRE(taken.success);
    const SolverSummary& s = taken.solves.front();
    if (!(s.converged() && s.convergenceTest == "iterate")) continue;
    const StepErrorCheck c = checkStepError(taken, run, tight, start);
    if (!c.checked) continue;
    const double ratio = c.error / s.iterateThreshold;
    INFO(s.iterateEstimate << ": error " << c.error << " m, threshold " << s.iterateThreshold << " m");
    if (s.iterateEstimate == "Newton correction") {
      ++corrections;
      worstCorrection = std::max(worstCorrection, ratio);
      CHECK(ratio <= 1.0);
    } else {
      ++residualPasses;
      worstResidual = std::max(worstResidual, ratio);
      // The residual estimate bounds the error while the step's Hessian is at least its inertia (solvers/
      // dynamics.h); a penalty against the ball's curved surface, and compression, take some of that away, so with
      // contact terms Newton's contraction may refuse a pass (without that, step 18 passed 1.045 times its
      // threshold from its tight solve after corrections that shrank ×0.98, ×1.2, ×0.92).
      CHECK(ratio <= 1.0);
    }
  }
  INFO("passes checked: " << corrections << " by the Newton correction (worst " << worstCorrection << " x), "
                          << residualPasses << " by the residual estimate (worst " << worstResidual << " x)");
  CHECK(corrections >= 5);  // measured: 12
  CHECK(residualPasses >= 5);
}

TEST_CASE("contact dynamics: the contact guards break at half the activation distance below a volume and at half "
          "the contact distance between samples",
          "[contact]") {
  // ShellContact::guardsBroken, which decides whether a solve at the iteration cap solves on
  // (DynamicsOptions::contactGuardSolves): two 0.2 m cloths 5.8 cm apart (r = 1.5 cm) over the floor.
  const TriMesh lower = square(0.2, 4, {0.0, 0.012, 0.0}), upper = square(0.2, 4, {0.0, 0.07, 0.0});
  const int n = lower.numVertices();
  const ShellProblem p = twoClothsOverFloor(lower, upper);
  ShellSystem system(p, AnalysisKind::Dynamics);
  REQUIRE(system.contact.pointCloud.state);
  const double eps = system.contact.volume.at(0).state->params.activationDistance;
  Eigen::VectorXd x(3 * 2 * n);
  for (int v = 0; v < 2 * n; ++v) x.segment<3>(3 * v) = p.mesh.V.row(v).transpose();
  system.contact.pointCloud.state->refresh(x);
  CHECK_FALSE(system.contact.guardsBroken(x, 0.5, 0.5));
  x[1] = -0.4 * eps;  // lower's vertex 0 below the floor, within half the activation distance
  CHECK_FALSE(system.contact.guardsBroken(x, 0.5, 0.5));
  x[1] = -0.6 * eps;
  CHECK(system.contact.guardsBroken(x, 0.5, 0.5));
  CHECK_FALSE(system.contact.guardsBroken(x, 0.7, 0.5));
  x[1] = 0.012;
  // upper's vertex 0 brought 1.2 cm above lower's (0.4 × 2r): the pair guard breaks at 0.5, not at 0.3.
  x.segment<3>(3 * n) = x.segment<3>(0) + Eigen::Vector3d(0.0, 0.012, 0.0);
  system.contact.pointCloud.state->refresh(x);
  CHECK(system.contact.guardsBroken(x, 0.5, 0.5));
  CHECK_FALSE(system.contact.guardsBroken(x, 0.5, 0.3));
}

TEST_CASE("contact dynamics: the contact guard options are validated", "[contact]") {
  ShellProblem p;
  p.mesh = square(0.2, 4, {0, 1, 0});
  p.material = cloth();
  ShellSystem system(p, AnalysisKind::Dynamics);
  DynamicsOptions o = options();
  o.contactGuardSolves = -1;
  CHECK_THROWS_WITH(DynamicsSolver(system, o), Catch::Contains("contactGuardSolves"));
  o = options();
  o.contactGuardSolves = 101;
  CHECK_THROWS_WITH(DynamicsSolver(system, o), Catch::Contains("contactGuardSolves"));
  for (double bad : {-0.1, std::nan(""), std::numeric_limits<double>::infinity()}) {
    o = options();
    o.contactGuardDepth = bad;
    CHECK_THROWS_WITH(DynamicsSolver(system, o), Catch::Contains("contactGuardDepth"));
  }
  for (double bad : {-0.1, 1.5, std::nan("")}) {
    o = options();
    o.contactGuardPairRatio = bad;
    CHECK_THROWS_WITH(DynamicsSolver(system, o), Catch::Contains("contactGuardPairRatio"));
  }
}

TEST_CASE("contact dynamics: the contact correction fraction is validated", "[contact]") {
  ShellProblem p;
  p.mesh = square(0.2, 4, {0, 1, 0});
  p.material = cloth();
  ShellSystem system(p, AnalysisKind::Dynamics);
  for (double bad : {-0.1, 1.5, std::nan("")}) {
    DynamicsOptions o = options();
    o.contactCorrectionFraction = bad;
    CHECK_THROWS_WITH(DynamicsSolver(system, o), Catch::Contains("contactCorrectionFraction"));
  }
}
