// A rigid solid pressed into a shell along a static path: its keyframes read with the load factor as time
// (RigidPath::readBy, LoadFactorHooks), the increments bounded so that it cannot pass through the shell between two
// solves (movingSolidIncrement), and the controls that solve for λ refused.
#include "core/mesh_generators.h"
#include "solvers/shell_system.h"
#include "solvers/statics.h"

#include <catch2/catch.hpp>

#include <cmath>
#include <string>
#include <vector>

using namespace jetshell;

namespace {

/// A 0.4 m square plate (E = 10 MPa, h = 1 mm, 16 × 16 cells) in the plane z = 0, its boundary fixed, no gravity,
/// and a ball of radius r whose lowest point starts `gap` above the plate's centre and is pressed down by `press`
/// at λ = keyTime (one keyframe), then held. Frictionless (statics has no friction).
ShellProblem pressedPlate(double r, double gap, double press, double keyTime = 1.0) {
  constexpr int n = 16;
  ShellProblem p;
  p.mesh = makeRectangleGrid(0.4, 0.4, n, n);
  p.material = ShellMaterialParamsFrom3dIsotropic(1e7, 0.3, 1000.0, 0.001);
  p.hasGravity = false;
  for (int v = 0; v < p.mesh.numVertices(); ++v) {
    const int i = v % (n + 1), j = v / (n + 1);
    if (i == 0 || j == 0 || i == n || j == n) p.prescribed.fixVertex(v, p.mesh.V.row(v).transpose());
  }
  RigidPath path;
  path.origin = {0.2, 0.2, gap + r};
  path.keyframes = {{keyTime, {0.0, 0.0, -press}, Eigen::Quaterniond::Identity()}};
  ContactParams c;
  c.frictionCoefficient = 0.0;
  p.volumes = {{std::make_shared<VolumeCollider>("punch", makeSphereShape(r), path), c}};
  return p;
}

constexpr int kCentre = 8 * 17 + 8;

/// Load control landing on `levels` equal levels, each equilibrium kept.
StaticsResult pressIn(ShellSystem& system, int levels, Eigen::VectorXd& x) {
  LoadSteppingOptions o;
  o.maxIncrement = 1.0 / levels;
  o.initialIncrement = 0.25 * o.maxIncrement;
  for (int k = 1; k < levels; ++k) o.levels.push_back(static_cast<double>(k) / levels);
  o.newton = staticNewtonOptions();
  x = system.restPositions();
  return solveStatics(system, x, o);
}

}  // namespace

TEST_CASE("static contact: a ball pressed into a plate by its keyframes is followed level by level",
          "[contact][statics]") {
  // The ball (r = 5 cm) starts 1 cm above the plate and ends 3 cm into its rest plane.
  const double r = 0.05, gap = 0.01, press = 0.04;
  ShellSystem system(pressedPlate(r, gap, press), AnalysisKind::Statics);
  CHECK(movingSolids(system) == std::vector<std::string>{"punch"});
  // 4 cm of travel against a bound of half its 5 cm half-width: at most two halves of the path.
  const double most = movingSolidIncrement(system, system.restPositions(), 0.0, 1.0);
  CHECK(most == 0.5);
  Eigen::VectorXd x;
  const StaticsResult result = pressIn(system, 8, x);
  REQUIRE(result.completed);
  int landed = 0;
  for (const LoadStepResult& s : result.steps) {
    if (!s.atLevel) continue;
    ++landed;
    REQUIRE(s.summary.converged());
    // The ball's lowest point at this λ; the plate's centre is under it, pushed into the band of the activation
    // distance ε = 5 mm below its surface where the penalty acts, or flat while the ball has not come down to ε.
    const double bottom = gap - press * s.loadFactor;
    const double z = s.x[3 * kCentre + 2];
    CAPTURE(s.loadFactor, bottom, z);
    if (bottom > 0.0049) {
      CHECK(std::abs(z) < 1e-9);
    } else {
      CHECK(z < bottom);
      CHECK(z > bottom - 0.005 - 1e-4);
    }
    // No sample of the plate is inside the ball where its path puts it at this λ.
    VolumeContactState& contact = *system.contact.volume[0].state;
    contact.time = s.loadFactor;
    CHECK(contact.minDistance(s.x) > 0.0);
  }
  CHECK(landed == 8);
  // The force on the ball is the reaction to the penalty's push on the plate: the sum of the penalty term's
  // gradient (the framework's derivative) over the vertices, upward.
  VolumeContactState& contact = *system.contact.volume[0].state;
  contact.time = 1.0;
  Eigen::VectorXd g = Eigen::VectorXd::Zero(x.size());
  EvalRequest request;
  request.gradient = &g;
  system.contact.volume[0].penalty->evaluate(x, request, EvalOptions{});
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (Eigen::Index v = 0; v < x.size() / 3; ++v) sum += g.segment<3>(3 * v);
  const Eigen::Vector3d force = contact.forceOnSolid(x, 1.0);
  CAPTURE(force.transpose(), sum.transpose());
  CHECK(force.z() > 1.0);
  CHECK((force - sum).norm() < 1e-9 * force.norm());
  CHECK(std::abs(force.x()) < 1e-6 * force.z());
  const auto forces = system.contact.solidForces(x, 1.0);
  REQUIRE(forces.size() == 1);
  CHECK(forces[0].first == "punch");
  CHECK((forces[0].second - force).norm() == 0.0);
  // Before the ball reaches the plate, no force.
  CHECK(contact.forceOnSolid(x, 0.0).norm() == 0.0);
  // Frictionless and elastic, the end state does not depend on the path's steps: two levels land on the same one.
  ShellSystem coarse(pressedPlate(r, gap, press), AnalysisKind::Statics);
  Eigen::VectorXd y;
  REQUIRE(pressIn(coarse, 2, y).completed);
  CHECK((x - y).lpNorm<Eigen::Infinity>() < 1e-6);
  CHECK(x[3 * kCentre + 2] < -0.025);
}

TEST_CASE("static contact: a moving solid drives the force scale as a prescribed motion would", "[contact][statics]") {
  // The plate's own weight (5e-6 N a vertex) would hold the residual to 5e-12 N while the ball pushes with newtons:
  // the ball's travel near the plate (4 cm) counts as prescribed motion, stiffness × 4 cm.
  ShellProblem p = pressedPlate(0.05, 0.01, 0.04);
  p.hasGravity = true;
  p.gravity = {0.0, 0.0, -9.81};
  ShellSystem system(p, AnalysisKind::Statics);
  CHECK(movingSolidTravel(system, system.restPositions(), 0.0, 1.0) == Approx(0.04));
  CHECK(movingSolidTravel(system, system.restPositions(), 0.0, 0.5) == Approx(0.02));
  Eigen::VectorXd x;
  const StaticsResult result = pressIn(system, 4, x);
  REQUIRE(result.completed);
  const SolverSummary& last = result.steps.back().summary;
  CHECK(last.forceScaleSource == "prescribed_motion");
  CHECK(last.forceScale == Approx(system.objective().scales().stiffness * 0.04));
}

TEST_CASE("static contact: a thin solid's increments are bounded so that it cannot pass through the plate",
          "[contact][statics]") {
  // A ball of radius 1 cm pressed 4 cm down from 1 cm above: at most half its 1 cm half-width per increment, so
  // at least 8 increments, whatever the levels ask.
  ShellSystem system(pressedPlate(0.01, 0.01, 0.04), AnalysisKind::Statics);
  const double most = movingSolidIncrement(system, system.restPositions(), 0.0, 1.0);
  CHECK(most == 0.125);
  Eigen::VectorXd x;
  const StaticsResult result = pressIn(system, 1, x);
  REQUIRE(result.completed);
  CHECK(result.steps.size() >= 8);
  for (std::size_t k = 1; k < result.steps.size(); ++k)
    CHECK(result.steps[k].loadFactor - result.steps[k - 1].loadFactor <= 0.125 + 1e-12);
  // The plate is under the ball, not above it: its centre below the ball's centre (now 2 cm below the plane).
  CHECK(x[3 * kCentre + 2] < -0.02);
  CHECK(system.contact.volume[0].state->minDistance(x) > 0.0);
  // A solid that would need more than kMaxMovingSolidIncrements increments is refused, by name.
  ShellSystem far(pressedPlate(1e-4, 0.01, 0.5), AnalysisKind::Statics);
  CHECK_THROWS_WITH(movingSolidIncrement(far, far.restPositions(), 0.0, 1.0),
                    Catch::Contains("the solid 'punch' moves") && Catch::Contains("more than 1024 of them"));
  // The solids move between their keyframes, not evenly over the path: a ball that makes its whole 4 cm move by
  // λ = 0.1 is bounded by that stretch (two halves of 0.05), not by the whole path (two of 0.5).
  ShellSystem early(pressedPlate(0.05, 0.01, 0.04, 0.1), AnalysisKind::Statics);
  CHECK(movingSolidIncrement(early, early.restPositions(), 0.0, 1.0) == Approx(0.05));
  // Its whole move within λ ∈ [0, 1e-9] would need 2e9 increments: refused, naming the stretch.
  ShellSystem jerk(pressedPlate(0.05, 0.01, 0.04, 1e-9), AnalysisKind::Statics);
  CHECK_THROWS_WITH(movingSolidIncrement(jerk, jerk.restPositions(), 0.0, 1.0),
                    Catch::Contains("between lambda = 0 and 1e-09"));
}

TEST_CASE("static contact: a moving solid needs load control, and only a static path moves it", "[contact][statics]") {
  ShellSystem system(pressedPlate(0.05, 0.01, 0.04), AnalysisKind::Statics);
  Eigen::VectorXd x = system.restPositions();
  LoadSteppingOptions o;
  o.newton = staticNewtonOptions();
  o.path.control = PathControl::ArcLength;
  CHECK_THROWS_WITH(solveStatics(system, x, o),
                    Catch::Contains("volume actor 'punch' moves with the load factor") &&
                        Catch::Contains("arcLength"));
  // A relaxation holds it where it is at t = 0; dynamics reads its whole path.
  const ShellSystem relaxation(pressedPlate(0.05, 0.01, 0.04), AnalysisKind::DynamicRelaxation);
  CHECK(relaxation.contact.volume[0].state->collider->path().isStatic());
  const ShellSystem dynamics(pressedPlate(0.05, 0.01, 0.04), AnalysisKind::Dynamics);
  CHECK_FALSE(dynamics.contact.volume[0].state->collider->path().isStatic());
  CHECK(movingSolids(system).size() == 1);
  // Branch switching solves for λ too (its correction and the branch it follows are by arc length): off.
  o.path.control = PathControl::Load;
  REQUIRE(o.branchSwitching);
  CHECK_FALSE(forMovingSolids(system, x, o).branchSwitching);
  ShellProblem withoutPunch = pressedPlate(0.05, 0.01, 0.04);
  withoutPunch.volumes.clear();
  const ShellSystem still(withoutPunch, AnalysisKind::Statics);
  REQUIRE(movingSolids(still).empty());
  CHECK(forMovingSolids(still, x, o).branchSwitching);
}
