#include "tests/test_util.h"
#include "core/mesh_generators.h"
#include "energies/shell/reference_state.h"
#include "core/topology.h"
#include "energies/shell/bending_term.h"
#include "energies/shell/membrane_term.h"
#include "energies/element_energy_term.h"
#include "energies/shell/shell_geometry.h"
#include "energies/shell/shell_terms.h"

#include <catch2/catch.hpp>
#include <ceres/jet.h>

#include <Eigen/Dense>

using namespace jetshell;

using jetshell::test::denseHessian;

namespace {

/// A grid with a curved rest shape, and a bent, perturbed configuration x of it (srand(seed)).
struct CurvedGrid {
  TriMesh mesh;
  Topology topo;
  ShellReference ref;
  Eigen::VectorXd x;
};

CurvedGrid curvedGrid(int nx, int ny, unsigned seed) {
  CurvedGrid g;
  g.mesh = makeRectangleGrid(1.0, 0.8, nx, ny);
  for (int v = 0; v < g.mesh.numVertices(); ++v)
    g.mesh.V(v, 2) = 0.2 * std::sin(2.0 * g.mesh.V(v, 0)) * g.mesh.V(v, 1);
  g.topo = buildTopology(g.mesh);
  g.ref = computeReference(g.mesh, g.topo);
  g.x = flatten(g.mesh.V);
  srand(seed);
  g.x += 0.15 * Eigen::VectorXd::Random(g.x.size());
  for (int v = 0; v < g.mesh.numVertices(); ++v) g.x[3 * v + 2] += 0.3 * std::cos(3.0 * g.x[3 * v]);
  return g;
}

/// The bending energy with edge rules as one 18-dof nested-Jet element per stencil: the whole stencil's
/// composite geometry (stencilSecondFundamentalForm, ruledBendingDensity), none of the stage graph's code.
struct RuledStencilEnergy {
  static constexpr int kVertices = 6;
  std::vector<StencilEdges> edges;
  std::vector<Sym2> origin;  // B per face
  ShellReference ref;
  double alpha = 0.0, beta = 0.0, scale = 1.0;
  template <typename T>
  T operator()(const T* x, int f) const {
    T b[3];
    stencilSecondFundamentalForm(x, edges[f], b);
    bool minimized[3];
    edges[f].minimizedEdges(minimized);
    return (scale * ref.area[f]) *
           ruledBendingDensity(b, origin[f].data(), ref.inverseMetric[f].data(), alpha, beta, minimized);
  }
};

/// That energy for `mesh` with `rule` on the boundary edges whose endpoints are both marked (the clamps' reference
/// normal: the face's rest normal), the page's free rule elsewhere; the curvature origin at b(*origin) with `scale`
/// when origin is given.
RuledStencilEnergy ruledStencilEnergy(const TriMesh& mesh, const Topology& topo, const ShellReference& ref,
                                      double alpha, double beta, const std::vector<char>& marked, EdgeRule rule,
                                      const Eigen::VectorXd* origin = nullptr, double scale = 1.0) {
  RuledStencilEnergy energy;
  energy.ref = ref;
  energy.origin = ref.secondFundamentalForm;
  energy.alpha = alpha;
  energy.beta = beta;
  energy.scale = scale;
  energy.edges.resize(static_cast<std::size_t>(mesh.numFaces()));
  for (int f = 0; f < mesh.numFaces(); ++f) {
    const Eigen::Vector3d x0 = mesh.V.row(mesh.F(f, 0));
    const Eigen::Vector3d r = (Eigen::Vector3d(mesh.V.row(mesh.F(f, 1))) - x0)
                                  .cross(Eigen::Vector3d(mesh.V.row(mesh.F(f, 2))) - x0)
                                  .normalized();
    StencilEdges& s = energy.edges[static_cast<std::size_t>(f)];
    for (int i = 0; i < 3; ++i) {
      s.boundary[i] = topo.faceNeighbors(f, i) < 0;
      const int a = mesh.F(f, (i + 1) % 3), b = mesh.F(f, (i + 2) % 3);
      if (s.boundary[i] && marked[static_cast<std::size_t>(a)] && marked[static_cast<std::size_t>(b)]) s.rule[i] = rule;
      for (int c = 0; c < 3; ++c) s.data[i].reference[c] = r[c];
    }
    if (origin != nullptr) {
      double xo[18] = {};
      for (int k = 0; k < 6; ++k) {
        const int v = topo.bendingStencil(f, k);
        for (int c = 0; c < 3 && v >= 0; ++c) xo[3 * k + c] = (*origin)[3 * v + c];
      }
      double b[3];
      stencilSecondFundamentalForm(xo, s, b);
      energy.origin[static_cast<std::size_t>(f)] = {b[0], b[1], b[2]};
    }
  }
  return energy;
}

/// The energy as one nested-Jet element per stencil.
EnergyTermPtr ruledNestedBending(RuledStencilEnergy energy, const Topology& topo, int numVertices) {
  StencilTable table;
  table.width = 6;
  table.ids.assign(topo.bendingStencil.data(), topo.bendingStencil.data() + topo.bendingStencil.size());
  return std::make_shared<ElementEnergyTerm<RuledStencilEnergy>>("bending_ruled_nested_jet", std::move(table),
                                                                 numVertices, std::move(energy));
}

/// Its Gauss–Newton Hessian Σ_f s·area_f J_bᵀ W'' J_b, dense: J_b of each stencil from first-order Jets of the
/// whole stencil's b, W'' from differences of the density's Jet gradient (exact: the density is quadratic in b).
Eigen::MatrixXd gaussNewtonReference(const RuledStencilEnergy& energy, const Topology& topo,
                                     const Eigen::VectorXd& x) {
  using J18 = ceres::Jet<double, 18>;
  using J3 = ceres::Jet<double, 3>;
  Eigen::MatrixXd H = Eigen::MatrixXd::Zero(x.size(), x.size());
  for (int f = 0; f < static_cast<int>(energy.edges.size()); ++f) {
    const StencilEdges& s = energy.edges[static_cast<std::size_t>(f)];
    J18 xe[18];
    for (int k = 0; k < 6; ++k) {
      const int v = topo.bendingStencil(f, k);
      for (int c = 0; c < 3; ++c) xe[3 * k + c] = J18(v >= 0 ? x[3 * v + c] : 0.0, 3 * k + c);
    }
    J18 b[3];
    stencilSecondFundamentalForm(xe, s, b);
    Eigen::Matrix<double, 3, 18> Jb;
    for (int r = 0; r < 3; ++r) Jb.row(r) = b[r].v.transpose();
    bool minimized[3];
    s.minimizedEdges(minimized);
    const auto gradient = [&](const double* at) {
      J3 z[3];
      for (int k = 0; k < 3; ++k) z[k] = J3(at[k], k);
      const J3 W = ruledBendingDensity(z, energy.origin[static_cast<std::size_t>(f)].data(),
                                       energy.ref.inverseMetric[static_cast<std::size_t>(f)].data(), energy.alpha,
                                       energy.beta, minimized);
      return Eigen::Vector3d(W.v);
    };
    const double b0[3] = {b[0].a, b[1].a, b[2].a};
    const Eigen::Vector3d g0 = gradient(b0);
    Eigen::Matrix3d Wbb;
    for (int k = 0; k < 3; ++k) {
      double bk[3] = {b0[0], b0[1], b0[2]};
      bk[k] += 1.0;
      Wbb.col(k) = gradient(bk) - g0;
    }
    const Eigen::Matrix<double, 18, 18> He =
        (energy.scale * energy.ref.area[static_cast<std::size_t>(f)]) * Jb.transpose() * Wbb * Jb;
    for (int a = 0; a < 6; ++a)
      for (int c = 0; c < 6; ++c) {
        const int va = topo.bendingStencil(f, a), vc = topo.bendingStencil(f, c);
        if (va >= 0 && vc >= 0) H.block<3, 3>(3 * va, 3 * vc) += He.block<3, 3>(3 * a, 3 * c);
      }
  }
  return H;
}

}  // namespace

TEST_CASE("bending: staged AD, staged analytic and nested-Jet reference agree") {
  const CurvedGrid c = curvedGrid(3, 2, 7);
  const Eigen::VectorXd& x = c.x;
  auto staged = makeBendingTerm(c.mesh, c.topo, c.ref, 0.3, 0.7);
  auto nested = makeBendingTermNestedJet(c.mesh, c.topo, c.ref, 0.3, 0.7);

  EvalOptions opt;
  Eigen::VectorXd gRef, gAd, gAn;
  double eRef, eAd, eAn;
  const Eigen::MatrixXd HRef = denseHessian(*nested, x, opt, gRef, eRef);
  opt.path = DerivativePath::AutoDiff;
  const Eigen::MatrixXd HAd = denseHessian(*staged, x, opt, gAd, eAd);
  opt.path = DerivativePath::Analytic;
  const Eigen::MatrixXd HAn = denseHessian(*staged, x, opt, gAn, eAn);
  CHECK(eAd == Approx(eRef).epsilon(1e-12));
  CHECK((gAd - gRef).norm() <= 1e-10 * gRef.norm());
  CHECK((gAn - gRef).norm() <= 1e-10 * gRef.norm());
  CHECK((HAd - HRef).norm() <= 1e-10 * HRef.norm());
  CHECK((HAn - HRef).norm() <= 1e-10 * HRef.norm());
}

TEST_CASE("bending: a projected Hessian projects each stencil's own block, as the nested-Jet reference does") {
  // Without projection the stage graph contracts the shared normals' curvature once and assembles it in one
  // stencil each (the same sum, other blocks); a projection must see each stencil's own Hessian instead.
  const CurvedGrid c = curvedGrid(4, 3, 5);
  const Eigen::VectorXd& x = c.x;
  auto term = makeBendingTerm(c.mesh, c.topo, c.ref, 0.3, 0.7);
  auto nested = makeBendingTermNestedJet(c.mesh, c.topo, c.ref, 0.3, 0.7);
  for (const PsdProjection projection : {PsdProjection::None, PsdProjection::Clamp, PsdProjection::Abs}) {
    for (const DerivativePath path : {DerivativePath::Analytic, DerivativePath::AutoDiff}) {
      INFO(toString(projection) << (path == DerivativePath::Analytic ? " analytic" : " AD"));
      EvalOptions opt;
      opt.projection = projection;
      Eigen::VectorXd gRef, g;
      double eRef, e;
      const Eigen::MatrixXd HRef = denseHessian(*nested, x, opt, gRef, eRef);
      opt.path = path;
      const Eigen::MatrixXd H = denseHessian(*term, x, opt, g, e);
      CHECK((H - HRef).norm() <= 1e-10 * HRef.norm());
      if (projection != PsdProjection::None) {
        const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> unprojected(denseHessian(*term, x, EvalOptions{}, g, e));
        CHECK(unprojected.eigenvalues().minCoeff() < -1e-6 * unprojected.eigenvalues().maxCoeff());
      }
    }
  }
}

TEST_CASE("bending: moment-free edges give the ruled nested-Jet reference's energy and derivatives") {
  const CurvedGrid c = curvedGrid(3, 2, 11);  // corner faces have two boundary edges, others one
  const TriMesh& mesh = c.mesh;
  const Eigen::VectorXd& x = c.x;
  const std::vector<char> all(static_cast<std::size_t>(mesh.numVertices()), 1);
  auto term = std::static_pointer_cast<BendingTerm>(makeBendingTerm(mesh, c.topo, c.ref, 0.3, 0.7));
  REQUIRE(term->setEdgeRule(all, EdgeRule::SecondOrderFree) > 0);
  const RuledStencilEnergy energy = ruledStencilEnergy(mesh, c.topo, c.ref, 0.3, 0.7, all, EdgeRule::SecondOrderFree);
  const EnergyTermPtr reference = ruledNestedBending(energy, c.topo, mesh.numVertices());
  const Eigen::MatrixXd HGaussNewton = gaussNewtonReference(energy, c.topo, x);

  Eigen::VectorXd gRef, gAd, gAn;
  double eRef, eAd, eAn;
  const Eigen::MatrixXd HRef = denseHessian(*reference, x, EvalOptions{}, gRef, eRef);
  for (const HessianModel hessian : {HessianModel::Exact, HessianModel::GaussNewton}) {
    INFO((hessian == HessianModel::Exact ? "exact" : "Gauss-Newton"));
    EvalOptions opt;
    opt.hessianModel = hessian;
    opt.path = DerivativePath::AutoDiff;
    const Eigen::MatrixXd HAd = denseHessian(*term, x, opt, gAd, eAd);
    opt.path = DerivativePath::Analytic;
    const Eigen::MatrixXd HAn = denseHessian(*term, x, opt, gAn, eAn);
    REQUIRE(std::abs(eRef) > 0.0);
    CHECK(eAd == Approx(eRef).epsilon(1e-12));
    CHECK(eAn == Approx(eRef).epsilon(1e-12));
    CHECK((gAd - gRef).norm() <= 1e-10 * gRef.norm());
    CHECK((gAn - gRef).norm() <= 1e-10 * gRef.norm());
    if (hessian == HessianModel::Exact) {
      CHECK((HAd - HRef).norm() <= 1e-10 * HRef.norm());
      CHECK((HAn - HRef).norm() <= 1e-10 * HRef.norm());
    } else {
      CHECK((HAd - HGaussNewton).norm() <= 1e-10 * HGaussNewton.norm());
      CHECK((HAn - HGaussNewton).norm() <= 1e-10 * HGaussNewton.norm());
    }
  }
  // The minimized density is below the page rule's on the same faces (the moment-free edges relax).
  auto page = makeBendingTerm(mesh, c.topo, c.ref, 0.3, 0.7);
  CHECK(term->evaluate(x, EvalRequest{}, EvalOptions{}) < page->evaluate(x, EvalRequest{}, EvalOptions{}));
}

TEST_CASE("membrane: AD and analytic paths agree") {
  TriMesh mesh = makeRectangleGrid(1.0, 0.8, 3, 2);
  const Topology topo = buildTopology(mesh);
  const ShellReference ref = computeReference(mesh, topo);
  auto term = makeMembraneTerm(mesh, ref, 3.0, 4.0);
  Eigen::VectorXd x = flatten(mesh.V);
  srand(3);
  x += 0.2 * Eigen::VectorXd::Random(x.size());
  EvalOptions opt;
  Eigen::VectorXd gAd, gAn;
  double eAd, eAn;
  opt.path = DerivativePath::AutoDiff;
  const Eigen::MatrixXd HAd = denseHessian(*term, x, opt, gAd, eAd);
  opt.path = DerivativePath::Analytic;
  const Eigen::MatrixXd HAn = denseHessian(*term, x, opt, gAn, eAn);
  CHECK((gAd - gAn).norm() <= 1e-12 * gAn.norm());
  CHECK((HAd - HAn).norm() <= 1e-12 * HAn.norm());
  // Finite differences of the energy against the gradient.
  const double h = 1e-6;
  Eigen::VectorXd gFd(x.size()), dummy;
  for (int i = 0; i < x.size(); ++i) {
    Eigen::VectorXd xp = x, xm = x;
    xp[i] += h;
    xm[i] -= h;
    gFd[i] = (term->evaluate(xp, {}, opt) - term->evaluate(xm, {}, opt)) / (2 * h);
  }
  CHECK((gFd - gAn).norm() <= 1e-7 * gAn.norm());
}

TEST_CASE("bending: clamped boundary edges match finite differences and resist rotation") {
  TriMesh mesh = makeRectangleGrid(1.0, 0.5, 4, 2);
  const Topology topo = buildTopology(mesh);
  const ShellReference ref = computeReference(mesh, topo);
  BendingTerm term(mesh, topo, ref, 0.2, 0.5);
  std::vector<char> mask(static_cast<std::size_t>(mesh.numVertices()), 0);
  for (int v = 0; v < mesh.numVertices(); ++v) mask[v] = mesh.V(v, 0) < 1e-9;  // the x = 0 edge
  REQUIRE(term.setClampedBoundary(mask) == 2);
  Eigen::VectorXd x = flatten(mesh.V);
  // A rigid rotation about the clamped edge costs energy once clamped, and nothing without the clamp.
  Eigen::VectorXd xr = x;
  for (int v = 0; v < mesh.numVertices(); ++v) {
    const double px = x[3 * v], pz = x[3 * v + 2];
    xr[3 * v] = std::cos(0.3) * px - std::sin(0.3) * pz;
    xr[3 * v + 2] = std::sin(0.3) * px + std::cos(0.3) * pz;
  }
  EvalOptions opt;
  CHECK(term.evaluate(x, {}, opt) == Approx(0.0).margin(1e-14));
  CHECK(term.evaluate(xr, {}, opt) > 1e-3);
  BendingTerm free(mesh, topo, ref, 0.2, 0.5);
  CHECK(free.evaluate(xr, {}, opt) == Approx(0.0).margin(1e-12));

  srand(11);
  x += 0.1 * Eigen::VectorXd::Random(x.size());
  Eigen::VectorXd gAn, gAd;
  double e1, e2;
  opt.path = DerivativePath::AutoDiff;
  const Eigen::MatrixXd HAd = denseHessian(term, x, opt, gAd, e1);
  opt.path = DerivativePath::Analytic;
  const Eigen::MatrixXd HAn = denseHessian(term, x, opt, gAn, e2);
  CHECK((HAd - HAn).norm() <= 1e-11 * HAn.norm());
  const double h = 1e-6;
  Eigen::MatrixXd HFd(x.size(), x.size());
  for (int i = 0; i < x.size(); ++i) {
    Eigen::VectorXd xp = x, xm = x, gp = Eigen::VectorXd::Zero(x.size()), gm = gp;
    xp[i] += h;
    xm[i] -= h;
    term.evaluate(xp, {&gp, nullptr, -1}, opt);
    term.evaluate(xm, {&gm, nullptr, -1}, opt);
    HFd.col(i) = (gp - gm) / (2 * h);
  }
  CHECK((HFd - HAn).norm() <= 1e-6 * HAn.norm());
}

TEST_CASE("shell terms: the bending graph gives the ruled nested-Jet reference, the membrane's graph its per-face "
          "element, with clamps and a moved origin") {
  TriMesh mesh = makeRectangleGrid(1.0, 0.8, 4, 3);
  for (int v = 0; v < mesh.numVertices(); ++v) mesh.V(v, 2) = 0.2 * std::sin(2.0 * mesh.V(v, 0)) * mesh.V(v, 1);
  const Topology topo = buildTopology(mesh);
  const ShellReference ref = computeReference(mesh, topo);
  Eigen::VectorXd x = flatten(mesh.V);
  srand(11);
  x += 0.1 * Eigen::VectorXd::Random(x.size());
  const Eigen::VectorXd origin = flatten(mesh.V) + 0.02 * Eigen::VectorXd::Random(x.size());
  std::vector<char> clamped(static_cast<std::size_t>(mesh.numVertices()), 0);
  for (int v = 0; v < mesh.numVertices(); ++v) clamped[v] = mesh.V(v, 0) < 1e-9;
  for (int variant = 0; variant < 4; ++variant) {
    BendingTerm bending(mesh, topo, ref, 0.3, 0.7);
    MembraneTerm perFace(mesh, ref, 3.0, 4.0), stagedM(mesh, ref, 3.0, 4.0);
    stagedM.setStaged(true);
    const EdgeRule rule = variant == 1 ? EdgeRule::ReferenceClamp : EdgeRule::MirroredClamp;
    if (variant == 1 || variant == 2) REQUIRE(bending.setEdgeRule(clamped, rule) > 0);
    if (variant == 3) {
      bending.setCurvatureOrigin(origin, 3.0);
      perFace.setStrainOrigin(origin, 3.0);
      stagedM.setStrainOrigin(origin, 3.0);
    }
    const std::vector<char> none(clamped.size(), 0);
    const RuledStencilEnergy energy =
        ruledStencilEnergy(mesh, topo, ref, 0.3, 0.7, variant == 1 || variant == 2 ? clamped : none, rule,
                           variant == 3 ? &origin : nullptr, variant == 3 ? 3.0 : 1.0);
    const EnergyTermPtr nested = ruledNestedBending(energy, topo, mesh.numVertices());
    const Eigen::MatrixXd HGaussNewton = gaussNewtonReference(energy, topo, x);
    for (DerivativePath path : {DerivativePath::AutoDiff, DerivativePath::Analytic}) {
      for (HessianModel hessian : {HessianModel::Exact, HessianModel::GaussNewton}) {
        INFO("variant " << variant << ", path " << static_cast<int>(path) << ", hessian " << static_cast<int>(hessian));
        EvalOptions opt;
        opt.path = path;
        opt.hessianModel = hessian;
        // The bending graph against the whole-stencil nested Jets, and its Gauss–Newton Hessian against J_bᵀ W'' J_b
        // from the whole stencil's Jets.
        Eigen::VectorXd gRef, g;
        double eRef, e;
        EvalOptions exact = opt;
        exact.hessianModel = HessianModel::Exact;
        const Eigen::MatrixXd HRef = denseHessian(*nested, x, exact, gRef, eRef);
        const Eigen::MatrixXd H = denseHessian(bending, x, opt, g, e);
        REQUIRE(std::abs(eRef) > 0.0);
        CHECK(e == Approx(eRef).epsilon(1e-12));
        CHECK((g - gRef).norm() <= 1e-10 * gRef.norm());
        if (hessian == HessianModel::Exact) CHECK((H - HRef).norm() <= 1e-10 * HRef.norm());
        if (hessian == HessianModel::GaussNewton) CHECK((H - HGaussNewton).norm() <= 1e-10 * HGaussNewton.norm());
        CHECK(bending.evaluate(x, EvalRequest{}, opt) == Approx(eRef).epsilon(1e-12));
        // A gradient alone: the reverse sweep (on the analytic path through the stages' pullback twins).
        Eigen::VectorXd gAlone = Eigen::VectorXd::Zero(x.size());
        CHECK(bending.evaluate(x, EvalRequest{&gAlone, nullptr, 0}, opt) == Approx(eRef).epsilon(1e-12));
        CHECK((gAlone - g).norm() <= 1e-12 * g.norm());
        // The membrane's graph against its per-face element: different summation orders only.
        Eigen::VectorXd gFace, gStaged;
        double eFace, eStaged;
        const Eigen::MatrixXd HFace = denseHessian(perFace, x, opt, gFace, eFace);
        const Eigen::MatrixXd HStaged = denseHessian(stagedM, x, opt, gStaged, eStaged);
        CHECK(std::abs(eStaged - eFace) <= 1e-12 * std::abs(eFace));
        CHECK((gStaged - gFace).norm() <= 1e-12 * gFace.norm());
        CHECK((HStaged - HFace).norm() <= 1e-12 * HFace.norm());
        Eigen::VectorXd gMembraneAlone = Eigen::VectorXd::Zero(x.size());
        CHECK(stagedM.evaluate(x, EvalRequest{&gMembraneAlone, nullptr, 0}, opt) == Approx(eFace).epsilon(1e-12));
        CHECK((gMembraneAlone - gFace).norm() <= 1e-12 * gFace.norm());
      }
    }
  }
}

TEST_CASE("membrane: the stage graph projects its blocks as the per-face element does") {
  // The staged membrane hands its blocks to the membrane's own projection (in-plane and normal parts,
  // energies/shell/membrane_projection.h) through the evaluator's element projector. Both projections give the
  // same matrix, so this checks the wiring (the block, its edges, the mode), not which projection ran: the hook's
  // own test (tests/core/stage_graph_test.cpp) checks that.
  TriMesh mesh = makeRectangleGrid(1.0, 0.8, 4, 3);
  const Topology topo = buildTopology(mesh);
  const ShellReference ref = computeReference(mesh, topo);
  Eigen::VectorXd x = 0.7 * flatten(mesh.V);  // compressed: the exact blocks are indefinite
  srand(5);
  x += 0.05 * Eigen::VectorXd::Random(x.size());
  MembraneTerm perFace(mesh, ref, 3.0, 4.0), staged(mesh, ref, 3.0, 4.0);
  staged.setStaged(true);
  Eigen::VectorXd g;
  double e;
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> unprojected(denseHessian(perFace, x, EvalOptions{}, g, e));
  REQUIRE(unprojected.eigenvalues().minCoeff() < -1e-6 * unprojected.eigenvalues().maxCoeff());
  for (const PsdProjection projection : {PsdProjection::Clamp, PsdProjection::Abs}) {
    for (const DerivativePath path : {DerivativePath::AutoDiff, DerivativePath::Analytic}) {
      INFO(toString(projection) << (path == DerivativePath::Analytic ? " analytic" : " AD"));
      EvalOptions opt;
      opt.projection = projection;
      opt.path = path;
      Eigen::VectorXd gFace, gStaged;
      double eFace, eStaged;
      const Eigen::MatrixXd HFace = denseHessian(perFace, x, opt, gFace, eFace);
      const Eigen::MatrixXd HStaged = denseHessian(staged, x, opt, gStaged, eStaged);
      CHECK((HStaged - HFace).norm() <= 1e-12 * HFace.norm());
      CHECK((gStaged - gFace).norm() <= 1e-12 * gFace.norm());
      const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> projected(HStaged);
      CHECK(projected.eigenvalues().minCoeff() >= -1e-12 * projected.eigenvalues().maxCoeff());
    }
  }
}

TEST_CASE("membrane on the Jets: the density Hessians it keeps follow the moduli and the strain origin") {
  // On the Jets a Hessian takes each face's density Hessian from the quadratic the term keeps (taken from Jets once
  // per λ, μ); the analytic twins are checked against the Jets by the conformance suite.
  CurvedGrid g = curvedGrid(4, 3, 23);
  for (bool stagedPath : {false, true}) {
    MembraneTerm membrane(g.mesh, g.ref, 3.0, 4.0);
    membrane.setStaged(stagedPath);
    EvalOptions ad, an;
    ad.path = DerivativePath::AutoDiff;
    an.path = DerivativePath::Analytic;
    for (int step = 0; step < 3; ++step) {
      INFO((stagedPath ? "staged" : "per face") << ", step " << step);
      if (step == 1) membrane.setParameterValues({7.0, 1.5});
      if (step == 2) membrane.setStrainOrigin(g.x + 0.01 * Eigen::VectorXd::Ones(g.x.size()), 2.0);
      Eigen::VectorXd gA, gB;
      double eA, eB;
      const Eigen::MatrixXd HA = denseHessian(membrane, g.x, ad, gA, eA);
      const Eigen::MatrixXd HB = denseHessian(membrane, g.x, an, gB, eB);
      CHECK((HA - HB).norm() <= 1e-12 * HB.norm());
      CHECK((gA - gB).norm() <= 1e-12 * gB.norm());
    }
  }
}

TEST_CASE("bending on the Jets: the density Hessians it keeps follow the moduli and the edge rules") {
  // On the Jets a Hessian takes each face's density Hessian from the quadratic the term keeps (taken from Jets once
  // per α, β and rules). After each change the Jets' Hessian must still be the nested-Jet element's.
  CurvedGrid g = curvedGrid(4, 3, 21);
  BendingTerm staged(g.mesh, g.topo, g.ref, 0.3, 0.7);
  const EnergyTermPtr nested = makeBendingTermNestedJet(g.mesh, g.topo, g.ref, 0.3, 0.7);
  EvalOptions ad;
  ad.path = DerivativePath::AutoDiff;
  std::vector<char> all(static_cast<std::size_t>(g.mesh.numVertices()), 1);
  for (int step = 0; step < 3; ++step) {
    INFO("step " << step);
    if (step == 1) staged.setParameterValues({0.9, 0.2});
    if (step == 2) staged.setEdgeRule(all, EdgeRule::SecondOrderFree);
    const std::vector<double> p = staged.parameterValues();
    // The nested-Jet reference at the same moduli (it has the page's free rule only: compared before the rule).
    Eigen::VectorXd gS, gN;
    double eS, eN;
    const Eigen::MatrixXd HS = denseHessian(staged, g.x, ad, gS, eS);
    if (step < 2) {
      nested->setParameterValues(p);
      const Eigen::MatrixXd HN = denseHessian(*nested, g.x, ad, gN, eN);
      CHECK((HS - HN).norm() <= 1e-12 * HN.norm());
    } else {
      // The rule's own twin on the analytic path (checked against the Jets by the conformance suite).
      EvalOptions an;
      an.path = DerivativePath::Analytic;
      const Eigen::MatrixXd HA = denseHessian(staged, g.x, an, gN, eN);
      CHECK((HS - HA).norm() <= 1e-12 * HA.norm());
    }
  }
}
