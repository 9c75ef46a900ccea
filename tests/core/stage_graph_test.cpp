#include "tests/test_util.h"
#include "core/hinge_stencil.h"
#include "core/mesh_generators.h"
#include "core/stage_graph.h"
#include "core/stage_graph_term.h"
#include "core/topology.h"
#include "energies/element_energy_term.h"

#include <catch2/catch.hpp>
#include <omp.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <numeric>
#include <type_traits>
#include <vector>

using namespace jetshell;
using jetshell::test::denseHessian;

namespace {

// A graph with every kind of input and layer, and the same energy written independently as one element:
//   per face:           n = (e0 × e1)/‖e0 × e1‖                              Shared, Difference inputs
//   per interior edge:  m = (n_A + n_B)/‖n_A + n_B‖² + 0.1 n_A × n_B         Shared, From a Shared layer
//   per element (edge): y = (m·e + ‖v‖², (m·v)(1 + m·m))                   Local, From Shared + leaves
//   energy:             E = y0² + sin(y1) + y0 y1                          Local, From a Local layer
// e = x_b − x_a (a Difference), v = x_c (a Vertex): the element is the edge's (a, b, c, d).
struct FaceNormal {
  static constexpr int kInputs = 6, kOutputs = 3;
  template <typename T>
  void operator()(const T* z, T* n, int) const {
    vec3(n) = vec3(z).cross(vec3(z + 3)).normalized();
  }
};
struct EdgeMix {
  static constexpr int kInputs = 6, kOutputs = 3;
  template <typename T>
  void operator()(const T* z, T* m, int) const {
    const auto a = vec3(z), b = vec3(z + 3);
    vec3(m) = (a + b) / (a + b).squaredNorm() + 0.1 * a.cross(b);
  }
};
struct Mix {
  static constexpr int kInputs = 9, kOutputs = 2;
  template <typename T>
  void operator()(const T* z, T* y, int) const {
    const auto m = vec3(z), e = vec3(z + 3), v = vec3(z + 6);
    y[0] = m.dot(e) + v.squaredNorm();
    y[1] = m.dot(v) * (1.0 + m.dot(m));
  }
};
struct Energy {
  static constexpr int kInputs = 2, kOutputs = 1;
  template <typename T>
  void operator()(const T* y, T* e, int) const {
    e[0] = y[0] * y[0] + sin(y[1]) + y[0] * y[1];
  }
};
using TestGraph = StageGraph<4, Shared<FaceNormal, 3, Difference, Difference>, Shared<EdgeMix, 4, From<0>, From<0>>,
                             Local<Mix, From<1>, Difference, Vertex>, Local<Energy, From<2>>>;
// The same with v = x_c − x_a: every leaf a Difference, so the evaluator works in the reduced coordinates
// x_k − x_0 and rebuilds slot 0's rows from the others'.
using DifferenceGraph = StageGraph<4, Shared<FaceNormal, 3, Difference, Difference>, Shared<EdgeMix, 4, From<0>, From<0>>,
                                   Local<Mix, From<1>, Difference, Difference>, Local<Energy, From<2>>>;
static_assert(!StageGraphEvaluator<TestGraph>::kReduced && StageGraphEvaluator<DifferenceGraph>::kReduced);
// The same stages with pullback twins (Jᵀw without J; core/stage.h), a Shared one and a Local one: on the analytic
// path a gradient alone, and the Local sweep of a contracted Hessian, pull the adjoints back through them.
struct PulledFaceNormal : FaceNormal {
  // With c = a × b: c̄ = (w − n (n·w))/‖c‖, ā = b × c̄, b̄ = c̄ × a.
  void pullback(const double* z, const double* n, int, const double* w, double* zbar) const {
    const Eigen::Vector3d a = vec3(z), b = vec3(z + 3), nv = vec3(n), wv = vec3(w);
    const Eigen::Vector3d cbar = (wv - nv * nv.dot(wv)) / a.cross(b).norm();
    vec3(zbar) = b.cross(cbar);
    vec3(zbar + 3) = cbar.cross(a);
  }
};
struct PulledMix : Mix {
  // y0 = m·e + ‖v‖², y1 = (m·v)(1 + m·m).
  void pullback(const double* z, const double*, int, const double* w, double* zbar) const {
    const Eigen::Vector3d m = vec3(z), e = vec3(z + 3), v = vec3(z + 6);
    const double mv = m.dot(v), q = 1.0 + m.dot(m);
    vec3(zbar) = w[0] * e + w[1] * (q * v + 2.0 * mv * m);
    vec3(zbar + 3) = w[0] * m;
    vec3(zbar + 6) = 2.0 * w[0] * v + w[1] * q * m;
  }
};
using PulledGraph = StageGraph<4, Shared<PulledFaceNormal, 3, Difference, Difference>,
                               Shared<EdgeMix, 4, From<0>, From<0>>, Local<PulledMix, From<1>, Difference, Vertex>,
                               Local<Energy, From<2>>>;

template <typename Graph = TestGraph>
Graph buildGraph(const TriMesh& mesh, const Topology& topo, const HingeStencils& l) {
  constexpr bool vertexInput = !std::is_same_v<Graph, DifferenceGraph>;
  Graph g(mesh.numVertices());
  g.template resize<0>(mesh.numFaces());
  for (int f = 0; f < mesh.numFaces(); ++f)
    g.template setInputs<0>(f, {difference(mesh.F(f, 0), mesh.F(f, 1)), difference(mesh.F(f, 0), mesh.F(f, 2))});
  g.template resize<1>(topo.numEdges());
  for (int e = 0; e < topo.numEdges(); ++e) {
    const int fa = topo.edgeFaces(e, 0), fb = topo.edgeFaces(e, 1);
    g.template setInputs<1>(e, {node(fa), node(fb >= 0 ? fb : fa)});
  }
  g.setElements(l.table);
  for (int i = 0; i < l.table.size(); ++i) {
    const int* v = l.table.element(i);
    g.template setInputs<2>(i, {node(l.edge[static_cast<std::size_t>(i)]), difference(v[0], v[1]),
                       vertexInput ? vertex(v[2]) : difference(v[0], v[2])});
    g.template setInputs<3>(i, {node(i)});
  }
  g.finalize();
  return g;
}

/// The same energy as one 12-dof element (the independent reference).
struct Reference {
  static constexpr int kVertices = 4;
  std::vector<std::array<std::array<int, 3>, 2>> corner;
  bool vertexInput = true;  // v = x_c (TestGraph), or x_c − x_a (DifferenceGraph)
  template <typename T>
  void mix(const T* x, int i, T* y) const {
    T n[2][3];
    for (int s = 0; s < 2; ++s) {
      const auto& c = corner[static_cast<std::size_t>(i)][static_cast<std::size_t>(s)];
      const T z[6] = {x[3 * c[1]] - x[3 * c[0]],         x[3 * c[1] + 1] - x[3 * c[0] + 1], x[3 * c[1] + 2] - x[3 * c[0] + 2],
                      x[3 * c[2]] - x[3 * c[0]],         x[3 * c[2] + 1] - x[3 * c[0] + 1], x[3 * c[2] + 2] - x[3 * c[0] + 2]};
      FaceNormal()(z, n[s], 0);
    }
    const T nn[6] = {n[0][0], n[0][1], n[0][2], n[1][0], n[1][1], n[1][2]};
    T m[3];
    EdgeMix()(nn, m, 0);
    T v[3] = {x[6], x[7], x[8]};
    if (!vertexInput)
      for (int k = 0; k < 3; ++k) v[k] -= x[k];
    const T z[9] = {m[0], m[1], m[2], x[3] - x[0], x[4] - x[1], x[5] - x[2], v[0], v[1], v[2]};
    Mix()(z, y, 0);
  }
  template <typename T>
  T operator()(const T* x, int i) const {
    T y[2], e[1];
    mix(x, i, y);
    Energy()(y, e, 0);
    return e[0];
  }
};

struct Case {
  TriMesh mesh = makeRectangleGrid(1.0, 0.8, 3, 2);
  Topology topo;
  HingeStencils l;
  Eigen::VectorXd x;
  Case() {
    for (int v = 0; v < mesh.numVertices(); ++v) mesh.V(v, 2) = 0.2 * std::sin(2.0 * mesh.V(v, 0)) * mesh.V(v, 1);
    topo = buildTopology(mesh);
    l = hingeStencils(mesh, topo);
    x = flatten(mesh.V);
    srand(7);
    x += 0.05 * Eigen::VectorXd::Random(x.size());
  }
};

}  // namespace

/// Both terms at x on the Jets: their energies and gradients must agree; the dense Hessians are returned for the
/// caller's checks, with the graph's energy and gradient.
struct Compared {
  Eigen::MatrixXd graph, reference;
  double energy = 0.0;
  Eigen::VectorXd gradient;
};
template <typename Graph>
Compared compareWithReference(StageGraphTerm<Graph>& graph, ElementEnergyTerm<Reference>& reference,
                              const Eigen::VectorXd& x, PsdProjection projection, HessianModel model = HessianModel::Exact) {
  EvalOptions opt;
  opt.path = DerivativePath::AutoDiff;
  opt.projection = projection;
  opt.hessianModel = model;
  Compared r;
  Eigen::VectorXd gR;
  double eR;
  r.graph = denseHessian(graph, x, opt, r.gradient, r.energy);
  r.reference = denseHessian(reference, x, opt, gR, eR);
  REQUIRE(std::abs(eR) > 0.1);
  CHECK(r.energy == Approx(eR).epsilon(1e-14));
  CHECK((r.gradient - gR).norm() <= 1e-13 * gR.norm());
  return r;
}

TEST_CASE("stage graph: value, gradient and Hessian equal the energy written as one nested-Jet element", "[stages]") {
  Case c;
  StageGraphTerm<TestGraph> graph("graph", buildGraph(c.mesh, c.topo, c.l));
  ElementEnergyTerm<Reference> reference("reference", c.l.table, c.mesh.numVertices(), Reference{c.l.corners});
  for (const PsdProjection projection : {PsdProjection::None, PsdProjection::Clamp}) {
    // No projection: the contracted sweep (each Shared node's curvature once); a projection: each element's own.
    const Compared r = compareWithReference(graph, reference, c.x, projection);
    CHECK((r.graph - r.reference).norm() <= 1e-13 * r.reference.norm());
    // The value alone and the gradient alone (the reverse sweep) are the same, up to the last bits: a stage's
    // value on doubles and on Jets may round differently (Eigen vectorizes the double case).
    EvalOptions opt;
    opt.path = DerivativePath::AutoDiff;
    opt.projection = projection;
    Eigen::VectorXd g = Eigen::VectorXd::Zero(c.x.size());
    CHECK(graph.evaluate(c.x, {}, opt) == Approx(r.energy).epsilon(1e-15));
    CHECK(graph.evaluate(c.x, {&g, nullptr, -1}, opt) == Approx(r.energy).epsilon(1e-15));
    CHECK((g - r.gradient).norm() <= 1e-14 * r.gradient.norm());
  }
}

TEST_CASE("stage graph: a graph of differences only gives the same derivatives in reduced coordinates", "[stages]") {
  Case c;
  StageGraphTerm<DifferenceGraph> graph("graph", buildGraph<DifferenceGraph>(c.mesh, c.topo, c.l));
  ElementEnergyTerm<Reference> reference("reference", c.l.table, c.mesh.numVertices(), Reference{c.l.corners, false});
  for (const HessianModel model : {HessianModel::Exact, HessianModel::GaussNewton})
    for (const PsdProjection projection : {PsdProjection::None, PsdProjection::Clamp}) {
      const Compared r = compareWithReference(graph, reference, c.x, projection, model);
      // A common translation changes nothing: every 3-row group of the assembled Hessian sums to zero.
      Eigen::MatrixXd sums = Eigen::MatrixXd::Zero(3, r.graph.cols());
      for (int v = 0; v < c.mesh.numVertices(); ++v) sums += r.graph.middleRows(3 * v, 3);
      CHECK(sums.norm() <= 1e-13 * r.graph.norm());
      if (model == HessianModel::Exact) CHECK((r.graph - r.reference).norm() <= 1e-13 * r.reference.norm());
    }
}

TEST_CASE("stage graph: an element projector projects the blocks it takes, the generic projection the rest", "[stages]") {
  Case c;
  StageGraphTerm<DifferenceGraph> graph("graph", buildGraph<DifferenceGraph>(c.mesh, c.topo, c.l));
  using Evaluator = StageGraphEvaluator<DifferenceGraph>;
  const int elements = c.l.table.size();
  EvalOptions opt;
  opt.projection = PsdProjection::Clamp;
  Eigen::VectorXd gGeneric, g;
  double eGeneric, e;
  const Eigen::MatrixXd generic = denseHessian(graph, c.x, opt, gGeneric, eGeneric);
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> unprojected(denseHessian(graph, c.x, EvalOptions{}, g, e));
  REQUIRE(unprojected.eigenvalues().minCoeff() < -1e-6 * unprojected.eigenvalues().maxCoeff());  // something to project

  // Declining every block: each goes to the generic projection, and the result is the same to the bit.
  std::atomic<int> calls{0};
  graph.setElementProjector([&](const Eigen::VectorXd&, int, const int*, Evaluator::WorkBlock&, PsdProjection mode) {
    CHECK(mode == PsdProjection::Clamp);
    ++calls;
    return false;
  });
  CHECK(denseHessian(graph, c.x, opt, g, e) == generic);
  CHECK(calls == elements);
  // Without a projection asked, the projector is never called.
  calls = 0;
  denseHessian(graph, c.x, EvalOptions{}, g, e);
  CHECK(calls == 0);

  // Taking every block: the generic projection stays out, and the base's row and column follow the block it
  // leaves (here zero: the whole Hessian is zero, the gradient and energy unchanged).
  graph.setElementProjector([&](const Eigen::VectorXd&, int, const int* ids, Evaluator::WorkBlock& block, PsdProjection) {
    CHECK(ids[0] >= 0);
    block.setZero();
    return true;
  });
  CHECK(denseHessian(graph, c.x, opt, g, e).norm() == 0.0);
  CHECK(g == gGeneric);
  CHECK(e == eGeneric);
}

TEST_CASE("stage graph: Gauss-Newton keeps the energy stage's curvature only", "[stages]") {
  Case c;
  StageGraphTerm<TestGraph> graph("graph", buildGraph(c.mesh, c.topo, c.l));
  EvalOptions opt;
  opt.path = DerivativePath::AutoDiff;
  opt.hessianModel = HessianModel::GaussNewton;
  Eigen::VectorXd g;
  double e;
  const Eigen::MatrixXd H = denseHessian(graph, c.x, opt, g, e);
  // Reference: Σ_elements J_yᵀ ∇²E(y) J_y, J_y the Jacobian of the energy stage's inputs from first-order Jets.
  const Reference ref{c.l.corners};
  Eigen::MatrixXd HR = Eigen::MatrixXd::Zero(c.x.size(), c.x.size());
  using J12 = ceres::Jet<double, 12>;
  for (int i = 0; i < c.l.table.size(); ++i) {
    const int* v = c.l.table.element(i);
    J12 xe[12];
    for (int k = 0; k < 4; ++k)
      for (int d = 0; d < 3; ++d) xe[3 * k + d] = J12(c.x[3 * v[k] + d], 3 * k + d);
    J12 y[2];
    ref.mix(static_cast<const J12*>(xe), i, y);
    Eigen::Matrix2d W;  // ∇²E(y) of E = y0² + sin(y1) + y0 y1
    W << 2.0, 1.0, 1.0, -std::sin(y[1].a);
    Eigen::Matrix<double, 2, 12> J;
    for (int r = 0; r < 2; ++r) J.row(r) = y[r].v.transpose();
    const Eigen::Matrix<double, 12, 12> block = J.transpose() * W * J;
    for (int a = 0; a < 4; ++a)
      for (int b = 0; b < 4; ++b) HR.block<3, 3>(3 * v[a], 3 * v[b]) += block.block<3, 3>(3 * a, 3 * b);
  }
  CHECK((H - HR).norm() <= 1e-13 * HR.norm());
}

TEST_CASE("stage graph: the same bits with 1 and 2 threads", "[stages]") {
  // Enough elements for the loops to run in parallel.
  TriMesh mesh = makeRectangleGrid(1.0, 1.0, 24, 24);
  for (int v = 0; v < mesh.numVertices(); ++v) mesh.V(v, 2) = 0.1 * std::sin(3.0 * mesh.V(v, 0) + mesh.V(v, 1));
  const Topology topo = buildTopology(mesh);
  const HingeStencils l = hingeStencils(mesh, topo);
  StageGraphTerm<TestGraph> graph("graph", buildGraph(mesh, topo, l));
  const Eigen::VectorXd x = flatten(mesh.V);
  const int threads = omp_get_max_threads();
  for (const PsdProjection projection : {PsdProjection::None, PsdProjection::Clamp}) {
    EvalOptions opt;
    opt.projection = projection;
    Eigen::VectorXd g1, g2;
    double e1, e2;
    omp_set_num_threads(1);
    const Eigen::MatrixXd H1 = denseHessian(graph, x, opt, g1, e1);
    omp_set_num_threads(2);
    const Eigen::MatrixXd H2 = denseHessian(graph, x, opt, g2, e2);
    omp_set_num_threads(threads);
    CHECK(e1 == e2);
    CHECK(g1 == g2);
    CHECK(H1 == H2);
  }
}

/// A 24 × 24 grid, waved; with `halves` its vertices and faces numbered left half first, then right half (a
/// garment's panels), so that the hinges, numbered by their vertices, follow.
/// The term's gradient alone at x on n threads, its energy into `energy`.
Eigen::VectorXd gradientAlone(EnergyTerm& term, const Eigen::VectorXd& x, const EvalOptions& opt, int n,
                              double& energy) {
  const int threads = omp_get_max_threads();
  omp_set_num_threads(n);
  Eigen::VectorXd g = Eigen::VectorXd::Zero(x.size());
  energy = term.evaluate(x, EvalRequest{&g, nullptr, 0}, opt);
  omp_set_num_threads(threads);
  return g;
}

/// The mesh's positions, each coordinate moved by up to ±amplitude (the same draw every call).
Eigen::VectorXd perturbed(const TriMesh& mesh, double amplitude) {
  Eigen::VectorXd x = flatten(mesh.V);
  srand(11);
  x += amplitude * Eigen::VectorXd::Random(x.size());
  return x;
}

TriMesh wavedGrid(bool halves) {
  TriMesh mesh = makeRectangleGrid(1.0, 1.0, 24, 24);
  for (int v = 0; v < mesh.numVertices(); ++v) mesh.V(v, 2) = 0.1 * std::sin(3.0 * mesh.V(v, 0) + mesh.V(v, 1));
  if (!halves) return mesh;
  const double middle = 0.5 * (mesh.V.col(0).minCoeff() + mesh.V.col(0).maxCoeff());
  std::vector<int> vertices(static_cast<std::size_t>(mesh.numVertices())), faces(static_cast<std::size_t>(mesh.numFaces()));
  std::iota(vertices.begin(), vertices.end(), 0);
  std::iota(faces.begin(), faces.end(), 0);
  std::stable_partition(vertices.begin(), vertices.end(), [&](int v) { return mesh.V(v, 0) < middle; });
  std::stable_partition(faces.begin(), faces.end(), [&](int f) {
    return mesh.V(mesh.F(f, 0), 0) + mesh.V(mesh.F(f, 1), 0) + mesh.V(mesh.F(f, 2), 0) < 3.0 * middle;
  });
  std::vector<int> newId(vertices.size());
  for (std::size_t i = 0; i < vertices.size(); ++i) newId[static_cast<std::size_t>(vertices[i])] = static_cast<int>(i);
  TriMesh out = mesh;
  for (std::size_t i = 0; i < vertices.size(); ++i) out.V.row(static_cast<Eigen::Index>(i)) = mesh.V.row(vertices[i]);
  for (std::size_t i = 0; i < faces.size(); ++i)
    for (int k = 0; k < 3; ++k) out.F(static_cast<Eigen::Index>(i), k) = newId[static_cast<std::size_t>(mesh.F(faces[i], k))];
  return out;
}

TEST_CASE("stage graph: the contracted Hessian and the gradient in windows equal the whole-mesh sweeps, with the same bits on 1 and 2 threads",
          "[stages]") {
  // Lanes of about four rows of hinges (nothing deferred), and of half a row (nodes read from three lanes, owners
  // deferred), on the grid numbered row by row; four lanes on the grid numbered by halves, whose phases pair each
  // lane with the lane it does not meet across the middle (lanes not alternating).
  for (const bool halves : {false, true}) {
    const TriMesh mesh = wavedGrid(halves);
    const Topology topo = buildTopology(mesh);
    const HingeStencils l = hingeStencils(mesh, topo);
    const Eigen::VectorXd x = perturbed(mesh, 0.02);
    TestGraph sweeps = buildGraph(mesh, topo, l);
    sweeps.replanWindows(0);
    REQUIRE(sweeps.windowPlan().empty());
    StageGraphTerm<TestGraph> a("sweeps", std::move(sweeps));
    const int threads = omp_get_max_threads();
    const std::vector<std::pair<int, int>> plans =
        halves ? std::vector<std::pair<int, int>>{{l.table.size() / 4, 50}} : std::vector<std::pair<int, int>>{{300, 50}, {30, 7}};
    for (const auto& [laneElements, window] : plans) {
      TestGraph windows = buildGraph(mesh, topo, l);
      windows.replanWindows(laneElements, window);
      const StageWindowPlan& plan = windows.windowPlan();
      REQUIRE(plan.lanes.size() >= 4);
      REQUIRE_FALSE(plan.unread[1].empty());  // the boundary edges' nodes: no element reads them
      if (laneElements == 30) {
        REQUIRE_FALSE(plan.cross[0].empty());
        REQUIRE_FALSE(plan.deferred.empty());
      }
      if (halves) REQUIRE(plan.phaseLanes[0] != std::vector<int>{0, 2});
      StageGraphTerm<TestGraph> b("windows", std::move(windows));
      const DerivativePath path = laneElements == 300 ? DerivativePath::AutoDiff : DerivativePath::Analytic;
      EvalOptions opt;  // exact, no projection: the contracted Hessian
      opt.path = path;
      Eigen::VectorXd gA, g1, g2;
      double eA, e1, e2;
      const Eigen::MatrixXd HA = denseHessian(a, x, opt, gA, eA);
      omp_set_num_threads(1);
      const Eigen::MatrixXd H1 = denseHessian(b, x, opt, g1, e1);
      omp_set_num_threads(2);
      const Eigen::MatrixXd H2 = denseHessian(b, x, opt, g2, e2);
      omp_set_num_threads(threads);
      // The same terms summed in another order.
      CHECK(e1 == Approx(eA).epsilon(1e-14));
      CHECK((g1 - gA).norm() <= 1e-14 * gA.norm());
      CHECK((H1 - HA).norm() <= 1e-14 * HA.norm());
      CHECK(e1 == e2);
      CHECK(g1 == g2);
      CHECK(H1 == H2);
      // A gradient without a Hessian: the gradient sweep's passes in the same windows.
      double fA, f1, f2;
      const Eigen::VectorXd hA = gradientAlone(a, x, opt, threads, fA), h1 = gradientAlone(b, x, opt, 1, f1),
                            h2 = gradientAlone(b, x, opt, 2, f2);
      CHECK(f1 == Approx(fA).epsilon(1e-14));
      CHECK((h1 - hA).norm() <= 1e-14 * hA.norm());
      CHECK((h1 - gA).norm() <= 1e-13 * gA.norm());  // and the Hessian path's gradient
      CHECK(f1 == f2);
      CHECK(h1 == h2);
    }
  }
}

TEST_CASE("stage graph: the pullback twins give the Jacobians' gradient and Hessian, whole-mesh and in windows",
          "[stages]") {
  STATIC_REQUIRE(HasPullbackTwin<PulledFaceNormal>::value);
  STATIC_REQUIRE(HasPullbackTwin<PulledMix>::value);
  STATIC_REQUIRE_FALSE(HasPullbackTwin<FaceNormal>::value);
  const TriMesh mesh = wavedGrid(false);
  const Topology topo = buildTopology(mesh);
  const HingeStencils l = hingeStencils(mesh, topo);
  // Less noise than the windows' test: no face nearly folds onto its neighbour, whose n_A + n_B near 0 would
  // amplify the last bits in which a value on doubles (a pulled node's) and on Jets differ.
  const Eigen::VectorXd x = perturbed(mesh, 0.002);
  const int threads = omp_get_max_threads();
  for (const int laneElements : {0, 30}) {
    INFO("lane elements " << laneElements);
    PulledGraph g = buildGraph<PulledGraph>(mesh, topo, l);
    g.replanWindows(laneElements, 7);
    REQUIRE(g.windowPlan().empty() == (laneElements == 0));
    StageGraphTerm<PulledGraph> term("pulled", std::move(g));
    EvalOptions ad, analytic;
    ad.path = DerivativePath::AutoDiff;
    analytic.path = DerivativePath::Analytic;
    // The Jets' path keeps every Jacobian (nothing is pulled on it): the reference.
    double eJ, e1, e2;
    const Eigen::VectorXd gJ = gradientAlone(term, x, ad, threads, eJ);
    const Eigen::VectorXd g1 = gradientAlone(term, x, analytic, 1, e1);
    const Eigen::VectorXd g2 = gradientAlone(term, x, analytic, 2, e2);
    CHECK(e1 == Approx(eJ).epsilon(1e-14));
    CHECK((g1 - gJ).norm() <= 1e-13 * gJ.norm());
    CHECK(e1 == e2);
    CHECK(g1 == g2);
    // The contracted Hessian's first-order sweep pulls the Local adjoints back through PulledMix.
    Eigen::VectorXd hJ, hA;
    double fJ, fA;
    const Eigen::MatrixXd HJ = denseHessian(term, x, ad, hJ, fJ);
    const Eigen::MatrixXd HA = denseHessian(term, x, analytic, hA, fA);
    CHECK(fA == Approx(fJ).epsilon(1e-14));
    CHECK((hA - hJ).norm() <= 1e-13 * hJ.norm());
    CHECK((HA - HJ).norm() <= 1e-13 * HJ.norm());
    CHECK((g1 - hJ).norm() <= 1e-13 * hJ.norm());
  }
}

TEST_CASE("stage graph: set-up rejects inputs that do not fit, naming the layer and the entity", "[stages]") {
  Case c;
  {
    TestGraph g = buildGraph(c.mesh, c.topo, c.l);
    g.setInputs<0>(2, {difference(0, 1), difference(0, c.mesh.numVertices())});
    CHECK_THROWS_WITH(g.finalize(), Catch::Contains("layer 0, entity 2") && Catch::Contains("out of range"));
  }
  {
    // An edge node reading two faces that share no edge spans more than its width of 4 vertices.
    TestGraph g = buildGraph(c.mesh, c.topo, c.l);
    g.setInputs<1>(0, {node(0), node(c.mesh.numFaces() - 1)});
    CHECK_THROWS_WITH(g.finalize(), Catch::Contains("layer 1, entity 0") && Catch::Contains("width"));
  }
  {
    // An element reading a vertex outside its stencil.
    TestGraph g = buildGraph(c.mesh, c.topo, c.l);
    const int* v = c.l.table.element(0);
    int outside = 0;
    while (outside == v[0] || outside == v[1] || outside == v[2] || outside == v[3]) ++outside;
    g.setInputs<2>(0, {node(c.l.edge[0]), difference(v[0], v[1]), vertex(outside)});
    CHECK_THROWS_WITH(g.finalize(), Catch::Contains("layer 2, element 0") && Catch::Contains("stencil"));
  }
  {
    TestGraph g = buildGraph(c.mesh, c.topo, c.l);
    CHECK_THROWS_AS(g.setInputs<0>(c.mesh.numFaces(), {difference(0, 1), difference(0, 2)}), std::out_of_range);
  }
}
