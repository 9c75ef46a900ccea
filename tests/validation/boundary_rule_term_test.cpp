#include "core/mesh_generators.h"
#include "energies/shell/reference_state.h"
#include "core/topology.h"
#include "energies/shell/shell_terms.h"
#include "validation/benchmark.h"
#include "validation/boundary_rule_term.h"

#include <catch2/catch.hpp>

#include <Eigen/Dense>

#include <cmath>

using namespace jetshell;
using namespace jetshell::validation;

namespace {

/// Tip deflection of the end-shear cantilever (nx × ny quads) under λ = 1e-4 of its load: the linear regime,
/// where the exact answer is P L³ / (3 EI).
double linearTipRatio(int nx, int ny, ClampKind clamp) {
  const BenchmarkCase c = findBenchmark("cantilever-end-shear").build({nx, ny}, clamp, QuadDiagonals::Uniform);
  ShellSystem system(c.problem, AnalysisKind::Statics);
  if (clamp == ClampKind::Mirrored) system.bending->setEdgeRule(c.problem.clampedVertices, EdgeRule::MirroredClamp);
  system.nodalForces->setLoadFactor(1e-4);
  NewtonSolver newton(system.objective(), benchmarkNewtonOptions());
  const Eigen::VectorXd X = system.restPositions();
  Eigen::VectorXd x = X;
  REQUIRE(newton.minimize(x).converged());
  return c.probes[1].read(x, X) / (1e-4 * 4.0 * 1000.0 / (3.0 * 100.0));
}

}  // namespace

TEST_CASE("boundary rules: Jet gradient and Hessian match central differences", "[validation]") {
  TriMesh mesh = makeRectangleGrid(2.0, 1.0, 4, 2);
  const Topology topo = buildTopology(mesh);
  const ShellReference ref = computeReference(mesh, topo);
  std::vector<char> clamped(static_cast<std::size_t>(mesh.numVertices()), 0);
  for (int j = 0; j <= 2; ++j) clamped[j * 5] = 1;
  BoundaryRules rules;
  rules.clampRule = BoundaryRule::MirroredClamp;
  rules.freeRule = BoundaryRule::SecondOrderFree;
  rules.symmetryPlanes.push_back({Eigen::Vector3d(0.0, 0.0, 0.0), Eigen::Vector3d(0.0, 1.0, 0.0)});
  auto term = makeBoundaryRuleTerm(mesh, topo, ref, 0.3, 0.7, clamped, rules);
  REQUIRE(term != nullptr);
  CHECK(term->stencils().size() == 10);  // every face with a boundary edge (uniform diagonals: 10 of them)
  Eigen::VectorXd x = flatten(mesh.V);
  srand(5);
  x += 0.1 * Eigen::VectorXd::Random(x.size());
  CHECK(term->evaluate(flatten(mesh.V), EvalRequest{}, EvalOptions{}) == Approx(0.0).margin(1e-14));
  HessianAssembler A;
  const int slot = A.addStencils(term->stencils());
  A.finalize(mesh.numVertices());
  A.setZero();
  Eigen::VectorXd g = Eigen::VectorXd::Zero(x.size());
  term->evaluate(x, EvalRequest{&g, &A, slot}, EvalOptions{});
  const Eigen::MatrixXd upper = Eigen::MatrixXd(A.matrix());
  Eigen::MatrixXd H = upper + upper.transpose();
  H.diagonal() -= upper.diagonal();
  const double h = 1e-6;
  Eigen::VectorXd gFd(x.size());
  Eigen::MatrixXd HFd(x.size(), x.size());
  for (Eigen::Index i = 0; i < x.size(); ++i) {
    Eigen::VectorXd xp = x, xm = x;
    xp[i] += h;
    xm[i] -= h;
    gFd[i] = (term->evaluate(xp, EvalRequest{}, EvalOptions{}) - term->evaluate(xm, EvalRequest{}, EvalOptions{})) /
             (2 * h);
    Eigen::VectorXd gp = Eigen::VectorXd::Zero(x.size()), gm = Eigen::VectorXd::Zero(x.size());
    term->evaluate(xp, EvalRequest{&gp}, EvalOptions{});
    term->evaluate(xm, EvalRequest{&gm}, EvalOptions{});
    HFd.col(i) = (gp - gm) / (2 * h);
  }
  REQUIRE(g.norm() > 1e-3);
  CHECK((g - gFd).norm() <= 1e-6 * g.norm());
  CHECK((H - HFd).norm() <= 1e-5 * H.norm());
}

TEST_CASE("boundary rules: with the mirrored clamp a linear cantilever converges at second order, with the reference normal at first", "[validation]") {
  // Measured w / w_exact: mirrored 1.00500, 1.00125; reference normal 1.47821, 1.23310; two-row 0.85500, 0.92625.
  const double m1 = linearTipRatio(10, 1, ClampKind::Mirrored), m2 = linearTipRatio(20, 2, ClampKind::Mirrored);
  CHECK(std::abs(m1 - 1.0) < 0.0055);
  CHECK(std::abs(m2 - 1.0) < 0.0014);
  CHECK(std::abs(m1 - 1.0) / std::abs(m2 - 1.0) > 3.5);
  const double n1 = linearTipRatio(10, 1, ClampKind::Normal), n2 = linearTipRatio(20, 2, ClampKind::Normal);
  CHECK(n1 > 1.4);  // soft: the mid-edge normal turns by half the face's rotation
  CHECK((n1 - 1.0) / (n2 - 1.0) < 2.2);
}

TEST_CASE("boundary rules: with uniform diagonals the bending energy of a twist z = k x y is consistent", "[validation]") {
  // With alternating diagonals the same field gives 2x the continuum energy on every face at every
  // resolution; with one diagonal direction only the boundary faces deviate (an O(h) excess).
  const double k = 1e-3;
  for (int n : {8, 16, 32}) {
    const TriMesh mesh = makeRectangleGrid(1.0, 1.0, n, n, QuadDiagonals::Uniform);
    const Topology topo = buildTopology(mesh);
    const ShellReference ref = computeReference(mesh, topo);
    auto bending = makeBendingTerm(mesh, topo, ref, 0.0, 1.0);
    Eigen::VectorXd x = flatten(mesh.V);
    for (int v = 0; v < mesh.numVertices(); ++v) x[3 * v + 2] = k * (mesh.V(v, 0) - 0.5) * (mesh.V(v, 1) - 0.5);
    const double ratio = bending->evaluate(x, EvalRequest{}, EvalOptions{}) / (k * k);  // ½·β·tr(κ²)·area = k²
    CHECK(ratio == Approx(1.0 + 1.0 / n).epsilon(1e-6));  // measured 1.1250, 1.0625, 1.0312
  }
}

namespace {

/// Bending energy (α = 0, β = 1) of z = f(x, y) on the unit square, n × n uniform-diagonal quads, over its
/// continuum value, with the free-edge rule `rule` on every edge.
template <typename Field>
double energyRatio(int n, BoundaryRule rule, Field field, double continuum) {
  const TriMesh mesh = makeRectangleGrid(1.0, 1.0, n, n, QuadDiagonals::Uniform);
  const Topology topo = buildTopology(mesh);
  const ShellReference ref = computeReference(mesh, topo);
  Eigen::VectorXd x = flatten(mesh.V);
  for (int v = 0; v < mesh.numVertices(); ++v) x[3 * v + 2] = field(mesh.V(v, 0) - 0.5, mesh.V(v, 1) - 0.5);
  double e = makeBendingTerm(mesh, topo, ref, 0.0, 1.0)->evaluate(x, EvalRequest{}, EvalOptions{});
  BoundaryRules rules;
  rules.freeRule = rule;
  if (auto t = makeBoundaryRuleTerm(mesh, topo, ref, 0.0, 1.0, {}, rules)) e += t->evaluate(x, EvalRequest{}, EvalOptions{});
  return e / continuum;
}

}  // namespace

TEST_CASE("boundary rules: the moment-free edge keeps a twist's energy and releases bending across the edge", "[validation]") {
  // A free edge carries no moment across it (M_nn = 0): the rule minimizes the boundary mid-edge normal's
  // component across the edge out. A twist z = kxy has no curvature across the square's edges, so its energy
  // is exact up to the four corner faces (O(h²)); the spec's rule reads the boundary faces' twist 1.5x (O(h)).
  const double k = 1e-3;
  auto twist = [k](double x, double y) { return k * x * y; };
  auto sphere = [k](double x, double y) { return 0.5 * k * (x * x + y * y); };
  for (int n : {8, 16, 32}) {
    const double t = energyRatio(n, BoundaryRule::SecondOrderFree, twist, k * k);
    const double tPage = energyRatio(n, BoundaryRule::PageFree, twist, k * k);
    const double s = energyRatio(n, BoundaryRule::SecondOrderFree, sphere, k * k);
    const double sPage = energyRatio(n, BoundaryRule::PageFree, sphere, k * k);
    WARN("n " << n << " twist " << t << " (page " << tPage << ") sphere " << s << " (page " << sPage << ")");
    CHECK(std::abs(t - 1.0) < 4.0 / (n * n));
    CHECK(std::abs(tPage - 1.0) > 0.5 / n);
    CHECK(s <= sPage + 1e-12);  // a minimum over the boundary normals
  }
}
