#include "core/mesh_generators.h"
#include "energies/shell/reference_state.h"
#include "core/topology.h"
#include "energies/shell/shell_terms.h"
#include "validation/benchmark.h"

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
double energyRatio(int n, EdgeRule rule, Field field, double continuum) {
  const TriMesh mesh = makeRectangleGrid(1.0, 1.0, n, n, QuadDiagonals::Uniform);
  const Topology topo = buildTopology(mesh);
  const ShellReference ref = computeReference(mesh, topo);
  Eigen::VectorXd x = flatten(mesh.V);
  for (int v = 0; v < mesh.numVertices(); ++v) x[3 * v + 2] = field(mesh.V(v, 0) - 0.5, mesh.V(v, 1) - 0.5);
  BendingTerm bending(mesh, topo, ref, 0.0, 1.0);
  bending.setEdgeRule(std::vector<char>(static_cast<std::size_t>(mesh.numVertices()), 1), rule);
  return bending.evaluate(x, EvalRequest{}, EvalOptions{}) / continuum;
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
    const double t = energyRatio(n, EdgeRule::SecondOrderFree, twist, k * k);
    const double tPage = energyRatio(n, EdgeRule::PageFree, twist, k * k);
    const double s = energyRatio(n, EdgeRule::SecondOrderFree, sphere, k * k);
    const double sPage = energyRatio(n, EdgeRule::PageFree, sphere, k * k);
    WARN("n " << n << " twist " << t << " (page " << tPage << ") sphere " << s << " (page " << sPage << ")");
    CHECK(std::abs(t - 1.0) < 4.0 / (n * n));
    CHECK(std::abs(tPage - 1.0) > 0.5 / n);
    CHECK(s <= sPage + 1e-12);  // a minimum over the boundary normals
  }
}
