#include "energies/shell/edge_rules.h"

#include "core/mesh_generators.h"
#include "energies/shell/shell_terms.h"
#include "tests/test_util.h"
#include "tools/checks/term_check.h"

#include <catch2/catch.hpp>

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>

using namespace jetshell;
using namespace jetshell::test;

namespace {

const EdgeRule kRules[] = {EdgeRule::PageFree, EdgeRule::ReferenceClamp, EdgeRule::MirroredClamp,
                           EdgeRule::SecondOrderFree, EdgeRule::SymmetryPlane};
const Eigen::Vector3d kPlane(0.3, 1.0, 0.2);  // a symmetry plane's normal (not unit: the term normalizes it)

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
  CHECK_THROWS_WITH(edgeRuleFromString("hinged"), Catch::Contains("page_free, reference_clamp, mirrored_clamp, "
                                                                   "second_order_free, symmetry_plane"));
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
  const V3<double> p = {{kPlane[0] / kPlane.norm(), kPlane[1] / kPlane.norm(), kPlane[2] / kPlane.norm()}};
  // The symmetry plane's mid-edge normal, (n − (n·p)p)/|n − (n·p)p|², and its rest origin (n = r at rest).
  auto inPlane = [&](const V3<double>& m) { return kelvinInversion(m - dot(m, p) * p); };
  const V3<double> X0 = load3(mesh.V.data()), X1{{mesh.V(1, 0), mesh.V(1, 1), mesh.V(1, 2)}},
                   X2{{mesh.V(2, 0), mesh.V(2, 1), mesh.V(2, 2)}};
  for (EdgeRule rule : kRules) {
    INFO(edgeRuleName(rule));
    BendingTerm term(mesh, topo, ref, 0.3, 0.7);
    CHECK(term.setEdgeRule({1, 1, 1}, rule, kPlane) == 3);
    CHECK(term.rigidInvariant() == (rule == EdgeRule::PageFree || rule == EdgeRule::SecondOrderFree));
    V3<double> nbar = n;
    if (rule == EdgeRule::ReferenceClamp) nbar = kelvinInversion(0.5 * (n + r));
    if (rule == EdgeRule::MirroredClamp) nbar = (1.0 / dot(n, r)) * r;
    if (rule == EdgeRule::SymmetryPlane) nbar = inPlane(n);
    double b[3], B[3] = {0.0, 0.0, 0.0};
    secondFundamentalForm(e0, e1, nbar, nbar, nbar, b);
    if (rule == EdgeRule::SymmetryPlane) secondFundamentalForm(X1 - X0, X2 - X0, inPlane(r), inPlane(r), inPlane(r), B);
    const double expected = ref.area[0] * bendingDensity(b, B, ref.inverseMetric[0].data(), 0.3, 0.7);
    const double energy = term.evaluate(x, EvalRequest{}, EvalOptions{});
    if (rule == EdgeRule::SecondOrderFree) {
      // Three moment-free edges release every curvature of a lone triangle: nothing is left.
      CHECK(std::abs(energy) <= 1e-15);
      continue;
    }
    CHECK(energy == Approx(expected).epsilon(1e-13).margin(1e-16));
    // A free lone triangle has no curvature (n̄ = n ⟂ its edges); the clamps and the plane see the tilt.
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
    for (HessianModel hessian : {HessianModel::Exact, HessianModel::GaussNewton}) {
      INFO(edgeRuleName(rule) << (hessian == HessianModel::Exact ? ", exact" : ", Gauss-Newton"));
      TermCheckOptions o;
      o.check.evalOptions.hessianModel = hessian;
      o.check.hessianIsExact = hessian == HessianModel::Exact;
      for (const std::string& f : termCheckFailures(
               [rule](const TermSetup& s) {
                 auto t = std::make_shared<BendingTerm>(s.mesh, s.topology, s.reference, 0.3, 0.7);
                 t->setEdgeRule(std::vector<char>(static_cast<std::size_t>(s.mesh.numVertices()), 1), rule, kPlane);
                 return t;
               },
               o))
        FAIL_CHECK(f);
    }
  }
}

TEST_CASE("edge rules: with the projected Hessian every rule's bending Hessian is positive semidefinite, "
          "and the Gauss-Newton one is without projecting") {
  ScopedThreads serial(1);
  const CheckMesh m = makeCheckMeshes().back();
  const Eigen::VectorXd x = makeCheckConfiguration(m, ConfigurationKind::Random, 7).x;
  for (EdgeRule rule : kRules) {
    for (HessianModel hessian : {HessianModel::Exact, HessianModel::GaussNewton}) {
      INFO(edgeRuleName(rule));
      BendingTerm t(m.mesh, m.topology, m.reference, 0.3, 0.7);
      t.setEdgeRule(std::vector<char>(static_cast<std::size_t>(m.mesh.numVertices()), 1), rule, kPlane);
      EvalOptions o;
      o.hessianModel = hessian;
      const Eigen::MatrixXd H = evaluateDense(t, x, o).hessian;
      o.projection = PsdProjection::Clamp;
      const Eigen::MatrixXd P = evaluateDense(t, x, o).hessian;
      const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> exact(H), projected(P);
      if (hessian == HessianModel::Exact)
        CHECK(exact.eigenvalues().minCoeff() <
              -1e-6 * exact.eigenvalues().maxCoeff());
      CHECK(projected.eigenvalues().minCoeff() >= -1e-12 * projected.eigenvalues().maxCoeff());
      if (hessian == HessianModel::GaussNewton) {
        // Jᵀ W'' J is positive semidefinite as it is, so the term does not project it (Newton's fallback
        // assembly relies on that: NewtonOptions::fallbackBendingHessian).
        CHECK(exact.eigenvalues().minCoeff() >= -1e-12 * exact.eigenvalues().maxCoeff());
        CHECK(P == H);
      }
    }
  }
}

TEST_CASE("edge rules: a moment-free edge's face takes its minimum over the boundary mid-edge normal n + a u") {
  // Independent of the closed form's constant directions: b(a) is built from the geometry (u the unit in-plane
  // direction across the edge, b linear in the mid-edge normals) and the quadratic f(a) = W_b(B − b(a)) is
  // minimized from three values. Moment-free rule on the y = 0 edges of a curved, twisted grid (one such edge
  // per face), the page's free rule elsewhere.
  TriMesh mesh = makeRectangleGrid(1.2, 0.8, 4, 3);
  for (int v = 0; v < mesh.numVertices(); ++v) mesh.V(v, 2) = 0.2 * std::sin(2.0 * mesh.V(v, 0)) * (mesh.V(v, 1) + 0.3);
  const Topology topo = buildTopology(mesh);
  const ShellReference ref = computeReference(mesh, topo);
  std::vector<char> bottom(static_cast<std::size_t>(mesh.numVertices()), 0);
  for (int v = 0; v < mesh.numVertices(); ++v) bottom[v] = mesh.V(v, 1) == 0.0;
  BendingTerm term(mesh, topo, ref, 0.3, 0.7);
  REQUIRE(term.setEdgeRule(bottom, EdgeRule::SecondOrderFree) == 4);
  Eigen::VectorXd x = flatten(mesh.V);
  for (int v = 0; v < mesh.numVertices(); ++v)
    x[3 * v + 2] +=
        0.5 * mesh.V(v, 0) * mesh.V(v, 1) + 0.3 * mesh.V(v, 0) * mesh.V(v, 0);
  double expected = 0.0, page = 0.0;
  for (int f = 0; f < mesh.numFaces(); ++f) {
    double xs[18] = {};
    bool boundary[3];
    for (int k = 0; k < 6; ++k)
      for (int c = 0; c < 3 && topo.bendingStencil(f, k) >= 0; ++c)
        xs[3 * k + c] = x[3 * topo.bendingStencil(f, k) + c];
    for (int i = 0; i < 3; ++i) boundary[i] = topo.bendingStencil(f, 3 + i) < 0;
    double b[3];
    stencilSecondFundamentalForm(xs, boundary, b);
    const double* B = ref.secondFundamentalForm[f].data();
    const double* P = ref.inverseMetric[f].data();
    auto W = [&](const double* bb) { return ref.area[f] * bendingDensity(bb, B, P, 0.3, 0.7); };
    double e = W(b);
    page += e;
    for (int i = 0; i < 3; ++i) {
      const int a = mesh.F(f, (i + 1) % 3), c = mesh.F(f, (i + 2) % 3);
      if (!boundary[i] || !bottom[a] || !bottom[c]) continue;
      const V3<double> p[3] = {load3(xs), load3(xs + 3), load3(xs + 6)};
      const V3<double> e0 = p[1] - p[0], e1 = p[2] - p[0], n = unitNormal(cross(e0, e1));
      const V3<double> u = unitNormal(cross(p[(i + 2) % 3] - p[(i + 1) % 3], n)), zero{{0.0, 0.0, 0.0}};
      V3<double> nb[3] = {zero, zero, zero};
      nb[i] = u;
      double delta[3];
      secondFundamentalForm(e0, e1, nb[0], nb[1], nb[2], delta);  // b(a) = b + a δ
      const double s = 0.1;
      const double bp[3] = {b[0] + s * delta[0], b[1] + s * delta[1], b[2] + s * delta[2]};
      const double bm[3] = {b[0] - s * delta[0], b[1] - s * delta[1], b[2] - s * delta[2]};
      const double g = (W(bp) - W(bm)) / (2.0 * s), q = (W(bp) + W(bm) - 2.0 * e) / (s * s);
      e -= 0.5 * g * g / q;
    }
    expected += e;
  }
  const double energy = term.evaluate(x, EvalRequest{}, EvalOptions{});
  CHECK(energy == Approx(expected).epsilon(1e-12));
  CHECK(energy < page - 1e-3 * page);  // the rule does release something here
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

TEST_CASE("edge rules: a moment-free face's derivatives follow alpha and beta set after the first evaluation") {
  // The analytic path keeps each moment-free face's quadratic form; a parameter change must renew it.
  ScopedThreads serial(1);
  const CheckMesh m = makeCheckMeshes().back();
  const Eigen::VectorXd x = makeCheckConfiguration(m, ConfigurationKind::Random, 3).x;
  const std::vector<char> all(static_cast<std::size_t>(m.mesh.numVertices()), 1);
  BendingTerm term(m.mesh, m.topology, m.reference, 0.3, 0.7);
  REQUIRE(term.setEdgeRule(all, EdgeRule::SecondOrderFree) > 0);
  EvalOptions analytic, ad;
  ad.path = DerivativePath::AutoDiff;
  const DenseDerivatives before = evaluateDense(term, x, analytic);
  term.setParameterValues({0.5, 1.9});
  BendingTerm fresh(m.mesh, m.topology, m.reference, 0.5, 1.9);
  fresh.setEdgeRule(all, EdgeRule::SecondOrderFree);
  const DenseDerivatives after = evaluateDense(term, x, analytic), jets = evaluateDense(term, x, ad),
                         reference = evaluateDense(fresh, x, analytic);
  const double gScale = jets.gradient.lpNorm<Eigen::Infinity>(), hScale = jets.hessian.lpNorm<Eigen::Infinity>();
  CHECK((after.gradient - before.gradient).lpNorm<Eigen::Infinity>() > 1e-3 * gScale);  // it did change
  CHECK((after.gradient - jets.gradient).lpNorm<Eigen::Infinity>() <= 1e-10 * gScale);
  CHECK((after.hessian - jets.hessian).lpNorm<Eigen::Infinity>() <= 1e-10 * hScale);
  CHECK((after.gradient - reference.gradient).lpNorm<Eigen::Infinity>() <= 1e-12 * gScale);
  CHECK(after.energy == Approx(jets.energy).epsilon(1e-12));
}
