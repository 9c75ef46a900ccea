// The boundary rules inside the bending term against the correction-term formulation they replace
// (bending with its built-in rules + validation's boundary-rule term): same energy, gradient and Hessian.
#include "core/mesh_generators.h"
#include "core/topology.h"
#include "energies/shell/shell_terms.h"
#include "tools/checks/derivative_check.h"
#include "validation/boundary_rule_term.h"

#include <catch2/catch.hpp>

#include <cmath>

using namespace jetshell;
using namespace jetshell::validation;

namespace {

double relDiff(double a, double b) { return std::abs(a - b) / std::max(std::abs(b), 1e-300); }

}  // namespace

TEST_CASE("rules in bending: second_order_free, symmetry_plane and mirrored_clamp equal bending + the correction term", "[validation]") {
  // A curved patch (normals at the y = 0 cut leave the plane, so the symmetry rule's rest origin moves),
  // clamped at x = 0, a symmetry plane y = 0, every other boundary edge moment-free.
  TriMesh mesh = makeRectangleGrid(1.2, 0.8, 5, 3);
  for (int v = 0; v < mesh.numVertices(); ++v)
    mesh.V(v, 2) = 0.15 * std::sin(2.0 * mesh.V(v, 0)) * (mesh.V(v, 1) + 0.3) + 0.1 * mesh.V(v, 0) * mesh.V(v, 0);
  const Topology topo = buildTopology(mesh);
  const ShellReference ref = computeReference(mesh, topo);
  const int n = mesh.numVertices();
  std::vector<char> clamped(static_cast<std::size_t>(n), 0), onPlane(static_cast<std::size_t>(n), 0);
  for (int v = 0; v < n; ++v) {
    clamped[v] = mesh.V(v, 0) == 0.0;
    onPlane[v] = mesh.V(v, 1) == 0.0;
  }
  const double alpha = 0.3, beta = 0.7;

  BendingTerm old(mesh, topo, ref, alpha, beta);
  old.setEdgeRule(clamped, EdgeRule::MirroredClamp);
  BoundaryRules rules;
  rules.clampRule = rules.builtInClampRule = BoundaryRule::MirroredClamp;
  rules.freeRule = BoundaryRule::SecondOrderFree;
  rules.symmetryPlanes.push_back({Eigen::Vector3d::Zero(), Eigen::Vector3d(0.0, 2.0, 0.0)});
  auto correction = makeBoundaryRuleTerm(mesh, topo, ref, alpha, beta, clamped, rules);
  REQUIRE(correction != nullptr);

  BendingTerm ruled(mesh, topo, ref, alpha, beta);
  ruled.setEdgeRule(std::vector<char>(static_cast<std::size_t>(n), 1), EdgeRule::SecondOrderFree);
  CHECK(ruled.setEdgeRule(onPlane, EdgeRule::SymmetryPlane, Eigen::Vector3d(0.0, 2.0, 0.0)) == 5);
  CHECK(ruled.setEdgeRule(clamped, EdgeRule::MirroredClamp) == 3);

  const Eigen::VectorXd X = flatten(mesh.V);
  CHECK(std::abs(ruled.evaluate(X, {}, {})) <= 1e-16);
  // Twisted (z += k x y) and bent, then perturbed.
  Eigen::VectorXd twisted = X, random = X;
  for (int v = 0; v < n; ++v) {
    twisted[3 * v + 2] += 0.4 * mesh.V(v, 0) * mesh.V(v, 1) + 0.2 * mesh.V(v, 0) * mesh.V(v, 0);
    for (int c = 0; c < 3; ++c) random[3 * v + c] += 0.05 * std::sin(1.3 + 2.1 * v + 0.7 * c);
  }
  for (const Eigen::VectorXd& x : {twisted, random}) {
    for (DerivativePath path : {DerivativePath::AutoDiff, DerivativePath::Analytic}) {
      EvalOptions o;
      o.path = path;
      const DenseDerivatives a = evaluateDense(old, x, o), c = evaluateDense(*correction, x, o);
      const DenseDerivatives b = evaluateDense(ruled, x, o);
      const double e = a.energy + c.energy;
      const Eigen::VectorXd g = a.gradient + c.gradient;
      const Eigen::MatrixXd H = a.hessian + c.hessian;
      INFO((path == DerivativePath::AutoDiff ? "autodiff" : "analytic") << ": E " << b.energy << " vs " << e);
      REQUIRE(std::abs(c.energy) > 1e-3 * std::abs(e));  // the rules really change the energy
      CHECK(relDiff(b.energy, e) <= 1e-13);
      CHECK((b.gradient - g).norm() <= 1e-12 * g.norm());
      CHECK((b.hessian - H).norm() <= 1e-12 * H.norm());
      WARN("energy " << relDiff(b.energy, e) << " gradient " << (b.gradient - g).norm() / g.norm() << " Hessian "
                     << (b.hessian - H).norm() / H.norm());
    }
  }
}
