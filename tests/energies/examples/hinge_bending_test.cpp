#include "tests/test_util.h"
#include "core/mesh_generators.h"
#include "core/topology.h"
#include "energies/examples/hinge_bending.h"

#include <catch2/catch.hpp>

using namespace jetshell;
using jetshell::test::denseHessian;

namespace {

/// A curved grid and a displaced configuration of it.
struct HingeCase {
  TriMesh mesh = makeRectangleGrid(1.0, 0.8, 3, 2);
  Topology topology;
  Eigen::VectorXd x;
  HingeCase() {
    for (int v = 0; v < mesh.numVertices(); ++v) mesh.V(v, 2) = 0.2 * std::sin(2.0 * mesh.V(v, 0)) * mesh.V(v, 1);
    topology = buildTopology(mesh);
    x = flatten(mesh.V);
    srand(11);
    x += 0.05 * Eigen::VectorXd::Random(x.size());
  }
};

}  // namespace

TEST_CASE("hinge bending: the staged term equals the same energy as one nested-Jet element", "[stages]") {
  HingeCase c;
  auto staged = makeHingeBendingTerm(c.mesh, c.topology, 0.7);
  auto nested = makeHingeBendingNestedJet(c.mesh, c.topology, 0.7);
  EvalOptions opt;
  opt.path = DerivativePath::AutoDiff;
  Eigen::VectorXd gS, gN;
  double eS, eN;
  const Eigen::MatrixXd HS = denseHessian(*staged, c.x, opt, gS, eS);
  const Eigen::MatrixXd HN = denseHessian(*nested, c.x, opt, gN, eN);
  REQUIRE(eN > 0.0);
  CHECK(eS == Approx(eN).epsilon(1e-13));
  CHECK((gS - gN).norm() <= 1e-12 * gN.norm());
  CHECK((HS - HN).norm() <= 1e-12 * HN.norm());
  // Zero at the rest shape (a curved one: rest angles are not zero).
  CHECK(std::abs(staged->evaluate(flatten(c.mesh.V), {}, opt)) <= 1e-20);
}

TEST_CASE("hinge bending: Gauss-Newton keeps only the energy stage's curvature", "[stages]") {
  HingeCase c;
  auto staged = makeHingeBendingTerm(c.mesh, c.topology, 0.7);
  EvalOptions exact, gn;
  exact.path = gn.path = DerivativePath::AutoDiff;
  gn.hessianModel = HessianModel::GaussNewton;
  Eigen::VectorXd gE, gG;
  double eE, eG;
  const Eigen::MatrixXd HE = denseHessian(*staged, c.x, exact, gE, eE);
  const Eigen::MatrixXd HG = denseHessian(*staged, c.x, gn, gG, eG);
  CHECK(eG == eE);
  CHECK((gG - gE).norm() <= 1e-14 * gE.norm());
  // The dropped curvature of the normals and of tan(θ/2) is not negligible away from rest, and the model keeps
  // only the energy's (a square of tan(θ/2)): positive semi-definite up to round-off.
  CHECK((HG - HE).norm() >= 1e-3 * HE.norm());
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(HG);
  CHECK(eig.eigenvalues().minCoeff() >= -1e-12 * eig.eigenvalues().cwiseAbs().maxCoeff());
}

TEST_CASE("hinge bending: shared stage results give the same bits with 1 and 2 threads", "[stages]") {
  // 1160 hinges: above the element loop's serial threshold, so two threads share the face-normal cache.
  const TriMesh mesh = makeRectangleGrid(1.0, 1.0, 20, 20);
  const Topology topology = buildTopology(mesh);
  auto term = makeHingeBendingTerm(mesh, topology, 0.7);
  Eigen::VectorXd x = flatten(mesh.V);
  for (int v = 0; v < mesh.numVertices(); ++v) x[3 * v + 2] = 0.1 * std::sin(5.0 * x[3 * v]) * std::cos(3.0 * x[3 * v + 1]);
  EvalOptions opt;
  opt.path = DerivativePath::AutoDiff;
  Eigen::VectorXd g1, g2;
  double e1, e2;
  Eigen::MatrixXd H1, H2;
  {
    jetshell::test::ScopedThreads one(1);
    H1 = denseHessian(*term, x, opt, g1, e1);
  }
  {
    jetshell::test::ScopedThreads two(2);
    H2 = denseHessian(*term, x, opt, g2, e2);
  }
  REQUIRE(e1 > 0.0);
  CHECK(e1 == e2);
  CHECK(g1 == g2);
  CHECK(H1 == H2);
}
