#include "energies/shell/edge_rules.h"

#include "energies/shell/shell_terms.h"
#include "tests/test_util.h"
#include "tools/checks/term_check.h"

#include <catch2/catch.hpp>

#include <Eigen/Geometry>

using namespace jetshell;
using namespace jetshell::test;

namespace {

const EdgeRule kRules[] = {EdgeRule::PageFree, EdgeRule::ReferenceClamp, EdgeRule::MirroredClamp};

TriMesh oneTriangle() {
  TriMesh mesh;
  mesh.V.resize(3, 3);
  mesh.V << 0, 0, 0, 1, 0, 0, 0.3, 0.8, 0;
  mesh.F.resize(1, 3);
  mesh.F << 0, 1, 2;
  return mesh;
}

}  // namespace

TEST_CASE("edge rules: names round-trip and unknown names are rejected") {
  for (EdgeRule rule : kRules) CHECK(edgeRuleFromString(edgeRuleName(rule)) == rule);
  CHECK_THROWS_WITH(edgeRuleFromString("hinged"), Catch::Contains("page_free, reference_clamp, mirrored_clamp"));
}

TEST_CASE("edge rules: a lone triangle's bending energy is the one its ghost normals define") {
  // Every edge of a lone triangle is a boundary edge; after tilting it, each rule's mid-edge normal is known in
  // closed form: page_free n̄ = n, reference_clamp n̄ = (n + r)/2 / |(n + r)/2|², mirrored_clamp n̄ = r/(n·r).
  const TriMesh mesh = oneTriangle();
  const Topology topo = buildTopology(mesh);
  const ShellReference ref = computeReference(mesh, topo);
  const Eigen::Matrix3d R = Eigen::AngleAxisd(0.4, Eigen::Vector3d(1, 0.2, 0).normalized()).toRotationMatrix();
  Eigen::VectorXd x = rigidlyMoved(flatten(mesh.V), R, Eigen::Vector3d(0.1, 0, 0));
  x[8] += 0.05;  // and bend it a little out of its rotated plane
  const V3<double> p0 = load3(x.data()), p1 = load3(x.data() + 3), p2 = load3(x.data() + 6);
  const V3<double> e0 = p1 - p0, e1 = p2 - p0;
  const V3<double> n = unitNormal(cross(e0, e1));
  const V3<double> r{{0.0, 0.0, 1.0}};
  for (EdgeRule rule : kRules) {
    INFO(edgeRuleName(rule));
    BendingTerm term(mesh, topo, ref, 0.3, 0.7);
    CHECK(term.setEdgeRule({1, 1, 1}, rule) == 3);
    CHECK(term.rigidInvariant() == (rule == EdgeRule::PageFree));
    V3<double> nbar;
    if (rule == EdgeRule::PageFree) nbar = n;
    if (rule == EdgeRule::ReferenceClamp) nbar = kelvinInversion(0.5 * (n + r));
    if (rule == EdgeRule::MirroredClamp) nbar = (1.0 / dot(n, r)) * r;
    double b[3];
    secondFundamentalForm(e0, e1, nbar, nbar, nbar, b);
    const double expected =
        ref.area[0] * bendingDensity(b, ref.secondFundamentalForm[0].data(), ref.inverseMetric[0].data(), 0.3, 0.7);
    CHECK(term.evaluate(x, EvalRequest{}, EvalOptions{}) == Approx(expected).epsilon(1e-13).margin(1e-16));
    // A free lone triangle has no curvature (n̄ = n ⟂ its edges); the clamps see the tilt.
    if (rule != EdgeRule::PageFree) REQUIRE(std::abs(expected) > 1e-4);
  }
}

TEST_CASE("edge rules: setClampedBoundary is the reference clamp, and an empty mask frees every edge") {
  const CheckMesh m = makeCheckMeshes().back();
  const Eigen::VectorXd x = makeCheckConfiguration(m, ConfigurationKind::Random, 5).x;
  const ShellMaterialParams mat;
  BendingTerm a(m.mesh, m.topology, m.reference, mat.bendingAlpha, mat.bendingBeta);
  BendingTerm b(m.mesh, m.topology, m.reference, mat.bendingAlpha, mat.bendingBeta);
  const std::vector<char> all(static_cast<std::size_t>(m.mesh.numVertices()), 1);
  CHECK(a.setClampedBoundary(all) == b.setEdgeRule(all, EdgeRule::ReferenceClamp));
  CHECK(a.evaluate(x, {}, {}) == b.evaluate(x, {}, {}));
  const double free = BendingTerm(m.mesh, m.topology, m.reference, mat.bendingAlpha, mat.bendingBeta).evaluate(x, {}, {});
  CHECK(std::abs(a.evaluate(x, {}, {}) - free) > 1e-6 * std::abs(free));
  CHECK(a.setClampedBoundary({}) == 0);
  CHECK(a.rigidInvariant());
  CHECK(a.evaluate(x, {}, {}) == free);
}

TEST_CASE("edge rules: every rule on every boundary edge passes the derivative checks, exact and Gauss-Newton") {
  ScopedThreads serial(1);
  for (EdgeRule rule : kRules) {
    for (BendingHessian hessian : {BendingHessian::Exact, BendingHessian::GaussNewton}) {
      INFO(edgeRuleName(rule) << (hessian == BendingHessian::Exact ? ", exact" : ", Gauss-Newton"));
      TermCheckOptions o;
      o.check.evalOptions.bendingHessian = hessian;
      o.check.hessianIsExact = hessian == BendingHessian::Exact;
      for (const std::string& f : termCheckFailures(
               [rule](const TermSetup& s) {
                 auto t = std::make_shared<BendingTerm>(s.mesh, s.topology, s.reference, 0.3, 0.7);
                 t->setEdgeRule(std::vector<char>(static_cast<std::size_t>(s.mesh.numVertices()), 1), rule);
                 return t;
               },
               o))
        FAIL_CHECK(f);
    }
  }
}

TEST_CASE("bending: a zero-area face gives a non-finite energy on the value path as on the derivative paths") {
  // The value path used to normalize with Eigen's normalized(), which leaves a zero vector finite, while the
  // derivative paths divide by |c| = 0: the same configuration was finite or NaN depending on the request.
  const CheckMesh m = makeCheckMeshes().front();
  Eigen::VectorXd x = flatten(m.mesh.V);
  x.segment<3>(3 * m.mesh.F(0, 2)) = x.segment<3>(3 * m.mesh.F(0, 0));  // face 0 collapses to a segment
  BendingTerm term(m.mesh, m.topology, m.reference, 0.3, 0.7);
  for (DerivativePath path : {DerivativePath::AutoDiff, DerivativePath::Analytic}) {
    EvalOptions o;
    o.path = path;
    Eigen::VectorXd g = Eigen::VectorXd::Zero(x.size());
    CHECK_FALSE(std::isfinite(term.evaluate(x, EvalRequest{}, o)));
    const double e = term.evaluate(x, EvalRequest{&g, nullptr, -1}, o);
    CHECK_FALSE((std::isfinite(e) && g.allFinite()));
  }
}
