// The cross derivatives of the history-dependent terms with their origin (core/origin_derivatives.h and the
// terms' originCrossDerivatives / centreCrossDerivatives) against differences of their gradients.
#include "core/origin_derivatives.h"

#include "core/mesh_generators.h"
#include "core/topology.h"
#include "energies/kinetic_terms.h"
#include "energies/shell/shell_terms.h"

#include <catch2/catch.hpp>

#include <cmath>
#include <functional>

using namespace jetshell;

namespace {

/// A bent, stretched configuration of the mesh (smooth, so the curvature changes).
Eigen::VectorXd deformed(const TriMesh& mesh, double amount, double phase) {
  Eigen::VectorXd x = flatten(mesh.V);
  for (int v = 0; v < mesh.numVertices(); ++v) {
    const double a = mesh.V(v, 0), b = mesh.V(v, 1);
    x[3 * v] += 0.05 * amount * a * b;
    x[3 * v + 2] += amount * std::sin(3.0 * a + phase) * std::cos(2.0 * b);
  }
  return x;
}

/// (g(x; y + εS_j) − g(x; y − εS_j)) / 2ε per column, g the gradient with the origin set by setOrigin.
Eigen::MatrixXd differences(EnergyTerm& term, const std::function<void(const Eigen::VectorXd&)>& setOrigin,
                            const Eigen::VectorXd& x, const Eigen::VectorXd& y, const Eigen::MatrixXd& S) {
  Eigen::MatrixXd out(x.size(), S.cols());
  const double eps = 1e-6;
  for (Eigen::Index j = 0; j < S.cols(); ++j) {
    Eigen::VectorXd gp = Eigen::VectorXd::Zero(x.size()), gm = gp;
    setOrigin(y + eps * S.col(j));
    term.evaluate(x, EvalRequest{&gp, nullptr, -1}, EvalOptions{});
    setOrigin(y - eps * S.col(j));
    term.evaluate(x, EvalRequest{&gm, nullptr, -1}, EvalOptions{});
    out.col(j) = (gp - gm) / (2.0 * eps);
  }
  setOrigin(y);
  return out;
}

}  // namespace

TEST_CASE("origin derivatives: stiffness damping's cross derivatives with its origin match differences of gradients",
          "[sensitivity]") {
  const TriMesh mesh = makeRectangleGrid(1.0, 0.6, 4, 3);
  const Topology topo = buildTopology(mesh);
  const ShellReference ref = computeReference(mesh, topo);
  ShellMaterialParams m;
  m.membraneLambda = 30.0;
  m.membraneMu = 20.0;
  m.bendingAlpha = 0.3;
  m.bendingBeta = 0.5;
  m.stiffnessDampingCoefficient = 0.02;
  StiffnessDampingTerms d = makeStiffnessDampingTerms(mesh, topo, ref, m);
  REQUIRE(d.membrane);
  REQUIRE(d.bending);
  std::vector<char> clamped(static_cast<std::size_t>(mesh.numVertices()), 0);
  for (int v = 0; v < mesh.numVertices(); ++v) clamped[static_cast<std::size_t>(v)] = mesh.V(v, 0) < 1e-9;
  d.bending->setClampedBoundary(clamped);  // boundary rules take part in the origin's curvature too
  const Eigen::VectorXd x = deformed(mesh, 0.1, 0.0), y = deformed(mesh, 0.07, 0.4);
  Eigen::MatrixXd S(x.size(), 3);
  for (Eigen::Index i = 0; i < x.size(); ++i)
    S.row(i) << std::sin(1.3 * i), std::cos(0.7 * i), (i % 3 == 2 ? 1.0 : 0.0);
  const double scale = 0.02 / 0.01;

  d.membrane->setStrainOrigin(y, scale);
  const Eigen::MatrixXd membrane = d.membrane->originCrossDerivatives(x, S);
  const Eigen::MatrixXd membraneFd =
      differences(*d.membrane, [&](const Eigen::VectorXd& o) { d.membrane->setStrainOrigin(o, scale); }, x, y, S);
  REQUIRE(membraneFd.norm() > 0.0);
  CHECK((membrane - membraneFd).norm() <= 1e-6 * membraneFd.norm());

  d.bending->setCurvatureOrigin(y, scale);
  const Eigen::MatrixXd bending = d.bending->originCrossDerivatives(x, S);
  const Eigen::MatrixXd bendingFd =
      differences(*d.bending, [&](const Eigen::VectorXd& o) { d.bending->setCurvatureOrigin(o, scale); }, x, y, S);
  REQUIRE(bendingFd.norm() > 0.0);
  CHECK((bending - bendingFd).norm() <= 1e-6 * bendingFd.norm());
}

TEST_CASE("origin derivatives: inertia's and mass damping's cross derivatives with their centre are -c M S",
          "[sensitivity]") {
  const TriMesh mesh = makeRectangleGrid(1.0, 0.6, 3, 2);
  const Eigen::VectorXd mass = Eigen::VectorXd::LinSpaced(mesh.numVertices(), 0.5, 2.0);
  auto term = makeMassDampingTerm(mass, 0.5);
  term->setParameterValues({0.8});  // the coefficient scales with α_R / α_R(built)
  const Eigen::VectorXd x = deformed(mesh, 0.1, 0.0), y = deformed(mesh, 0.05, 1.0);
  term->setCentre(y, 3.0);
  Eigen::MatrixXd S(x.size(), 2);
  for (Eigen::Index i = 0; i < x.size(); ++i) S.row(i) << std::sin(1.1 * i), 1.0;
  const Eigen::MatrixXd fd = differences(*term, [&](const Eigen::VectorXd& c) { term->setCentre(c, 3.0); }, x, y, S);
  CHECK((term->centreCrossDerivatives(S) - fd).norm() <= 1e-8 * fd.norm());
}
