// Bending term: the term's state (rules, reference, parameters, curvature origin) and its derivatives with
// respect to parameters and origin. Its energy, gradient and Hessian come from its stage graph
// (bending_graph.cpp).
#include "energies/shell/bending_term.h"

#include "core/flatten.h"
#include "core/origin_derivatives.h"
#include "core/parameter_derivatives.h"
#include "core/stage_derivatives.h"
#include "energies/element_energy_term.h"
#include "energies/shell/shell_geometry.h"
#include "energies/shell/shell_terms.h"

#include <Eigen/Geometry>

#include <array>

namespace jetshell {
namespace {

using Mat3 = Eigen::Matrix3d;
using Vec3 = Eigen::Vector3d;

}  // namespace

BendingTerm::BendingTerm(const TriMesh& mesh, const Topology& topo, const ShellReference& ref, double alpha,
                         double beta)
    : F_(mesh.F), topo_(topo), ref_(ref), alpha_(alpha), beta_(beta) {
  const int nf = mesh.numFaces();
  table_.width = 6;
  table_.ids.assign(topo.bendingStencil.data(), topo.bendingStencil.data() + topo.bendingStencil.size());
  schedule_ = scheduleElements(table_, mesh.numVertices());
  const int ne = topo.numEdges();
  rules_.assign(static_cast<std::size_t>(ne), EdgeRule::PageFree);
  ruleData_.resize(static_cast<std::size_t>(ne));
  for (int e = 0; e < ne; ++e) {
    const int f = topo.edgeFaces(e, 0);
    const Vec3 x0 = mesh.V.row(mesh.F(f, 0));
    const Vec3 r = (Vec3(mesh.V.row(mesh.F(f, 1))) - x0).cross(Vec3(mesh.V.row(mesh.F(f, 2))) - x0).normalized();
    for (int c = 0; c < 3; ++c) ruleData_[e].reference[c] = r[c];
  }
  minimized_.assign(static_cast<std::size_t>(nf), {false, false, false});
  restPositions_ = flatten(mesh.V);
  givenForm_ = ref.secondFundamentalForm;
  buildGraph();
}

int BendingTerm::setEdgeRule(const std::vector<char>& vertexMask, EdgeRule rule, const Eigen::Vector3d& axis) {
  if (rule == EdgeRule::Count) throw InputError(name_ + ": invalid edge rule");
  Vec3 p = Vec3::Zero();
  if (rule == EdgeRule::SymmetryPlane) {
    if (!(axis.allFinite() && axis.norm() > 0.0))
      throw InputError(name_ + ": a symmetry plane's normal must be finite and nonzero");
    p = axis.normalized();
  }
  int count = 0;
  for (int e = 0; e < topo_.numEdges(); ++e) {
    if (!topo_.isBoundaryEdge(e)) continue;
    const int a = topo_.edges(e, 0), b = topo_.edges(e, 1);
    if (a < static_cast<int>(vertexMask.size()) && b < static_cast<int>(vertexMask.size()) && vertexMask[a] &&
        vertexMask[b]) {
      rules_[e] = rule;
      for (int c = 0; c < 3; ++c) ruleData_[e].axis[c] = p[c];
      ++count;
    }
  }
  updateRuleState();
  return count;
}

void BendingTerm::updateRuleState() {
  quadraticStale_ = true;
  rigidEdges_ = 0;
  for (int e = 0; e < topo_.numEdges(); ++e)
    if (topo_.isBoundaryEdge(e) && ruleSeesRigidMotion(rules_[e])) ++rigidEdges_;
  const int nf = static_cast<int>(F_.rows());
  for (int f = 0; f < nf; ++f) {
    const StencilEdges s = stencilEdges(f);
    bool m[3];
    s.minimizedEdges(m);
    minimized_[f] = {m[0], m[1], m[2]};
    if (originMoved_) continue;
    // The rest origin: B as given, plus b(X) with the face's rules minus b(X) with the page's (nonzero only
    // where a rule's ghost at rest is not the face's own normal: a symmetry plane the face's normal leaves).
    ref_.secondFundamentalForm[f] = givenForm_[f];
    if (!(s.rule[0] == EdgeRule::SymmetryPlane || s.rule[1] == EdgeRule::SymmetryPlane ||
          s.rule[2] == EdgeRule::SymmetryPlane))
      continue;
    double X[18] = {};
    for (int k = 0; k < 6; ++k) {
      const int v = topo_.bendingStencil(f, k);
      for (int c = 0; c < 3 && v >= 0; ++c) X[3 * k + c] = restPositions_[3 * v + c];
    }
    double ruled[3], page[3];
    stencilSecondFundamentalForm(X, s, ruled);
    stencilSecondFundamentalForm(X, s.boundary, page);
    for (int k = 0; k < 3; ++k) ref_.secondFundamentalForm[f][k] += ruled[k] - page[k];
  }
}

int BendingTerm::setClampedBoundary(const std::vector<char>& vertexMask) {
  std::fill(rules_.begin(), rules_.end(), EdgeRule::PageFree);
  return setEdgeRule(vertexMask, EdgeRule::ReferenceClamp);
}

void BendingTerm::makeStiffnessDamping(double betaR) {
  if (!(std::isfinite(betaR) && betaR > 0.0)) throw InputError(name_ + ": beta_R must be finite and > 0");
  dampingReference_ = dampingValue_ = betaR;
}

std::vector<std::string> BendingTerm::parameterNames() const {
  if (dampingReference_ > 0.0) return {"beta_R", "alpha", "beta"};
  return {"alpha", "beta"};
}

std::vector<double> BendingTerm::parameterValues() const {
  if (dampingReference_ > 0.0) return {dampingValue_, alpha_, beta_};
  return {alpha_, beta_};
}

void BendingTerm::setParameterValues(const std::vector<double>& values) {
  validateParameterValues(name_, parameterNames(), values);
  const std::size_t k = dampingReference_ > 0.0 ? 1 : 0;
  if (k == 1) dampingValue_ = values[0];
  alpha_ = values[k];
  beta_ = values[k + 1];
}

StencilEdges BendingTerm::stencilEdges(int f) const {
  StencilEdges s;
  for (int i = 0; i < 3; ++i) {
    const int e = topo_.faceEdges(f, i);
    s.boundary[i] = topo_.faceNeighbors(f, i) < 0;
    s.rule[i] = rules_[e];
    s.data[i] = ruleData_[e];
  }
  return s;
}

void BendingTerm::evaluateParameterDerivatives(const Eigen::VectorXd& x, ParameterDerivatives& out) {
  const int nf = static_cast<int>(F_.rows());
  std::vector<StencilEdges> edges(static_cast<std::size_t>(nf));
  for (int f = 0; f < nf; ++f) edges[f] = stencilEdges(f);
  // The whole stencil's energy as a function of positions and parameters (the same templated geometry the
  // stages differentiate); duals seeded on the parameters give ∂E/∂p and ∂²E/∂x∂p.
  auto energy = [&](const auto* xe, const auto* p, int f) {
    using T = std::remove_const_t<std::remove_pointer_t<decltype(xe)>>;
    T b[3];
    stencilSecondFundamentalForm(xe, edges[f], b);
    const double* B = ref_.secondFundamentalForm[f].data();
    const double* P = ref_.inverseMetric[f].data();
    const bool* m = minimized_[f].data();
    if (dampingReference_ > 0.0)
      return (scale_ * ref_.area[f] / dampingReference_) * p[0] *
             ruledBendingDensity(b, B, P, p[1], p[2], m);
    return (scale_ * ref_.area[f]) * ruledBendingDensity(b, B, P, p[0], p[1], m);
  };
  const std::vector<double> p = parameterValues();
  resetParameterDerivatives(out, x.size(), static_cast<int>(p.size()));
  if (dampingReference_ > 0.0) {
    addParameterDerivatives<6, 3>(table_, x, p.data(), energy, out);
  } else {
    addParameterDerivatives<6, 2>(table_, x, p.data(), energy, out);
  }
}

Eigen::MatrixXd BendingTerm::originCrossDerivatives(const Eigen::VectorXd& x, const Eigen::MatrixXd& S) const {
  Eigen::MatrixXd out = Eigen::MatrixXd::Zero(x.size(), S.cols());
  if (!originMoved_ || S.cols() == 0) return out;
  const int nf = static_cast<int>(F_.rows());
  std::vector<StencilEdges> edges(static_cast<std::size_t>(nf));
  for (int f = 0; f < nf; ++f) edges[f] = stencilEdges(f);
  // scale · area · W_b(κ) with κ = b(y) − b(x) (the origin's curvature is b(y), the same stencil and edge
  // rules): passed as b(x) − b(y) against a zero origin.
  const double zero[3] = {0.0, 0.0, 0.0};
  const double s = energyScale();
  auto energy = [&](const auto* xe, const auto* ye, int f) {
    using T = std::remove_const_t<std::remove_pointer_t<decltype(xe)>>;
    T bx[3], by[3];
    stencilSecondFundamentalForm(xe, edges[f], bx);
    stencilSecondFundamentalForm(ye, edges[f], by);
    const T d[3] = {bx[0] - by[0], bx[1] - by[1], bx[2] - by[2]};
    return (s * ref_.area[f]) *
           ruledBendingDensity(d, zero, ref_.inverseMetric[f].data(), alpha_, beta_, minimized_[f].data());
  };
  addOriginCrossDerivatives<6>(table_, x, origin_, S, energy, out);
  return out;
}

void BendingTerm::setCurvatureOrigin(const Eigen::VectorXd& xOrigin, double scale) {
  origin_ = xOrigin;
  scale_ = scale;
  originMoved_ = true;
  graphCurvatureOrigin(xOrigin);
}

void BendingTerm::updateRuledQuadratics(bool everyFace) {
  if (!quadraticStale_ && quadraticAlpha_ == alpha_ && quadraticBeta_ == beta_ && (quadraticEveryFace_ || !everyFace))
    return;
  const int nf = static_cast<int>(F_.rows());
  ruledQuadratic_.assign(static_cast<std::size_t>(nf), Mat3::Zero());
  const double zero[3] = {0.0, 0.0, 0.0};
  for (int f = 0; f < nf; ++f) {
    const bool* m = minimized_[f].data();
    if (!everyFace && !(m[0] || m[1] || m[2])) continue;
    const double* P = ref_.inverseMetric[f].data();
    auto density = [&](const auto* z) { return ruledBendingDensity(z, zero, P, alpha_, beta_, m); };
    double W;
    Vec3 w;
    scalarStageDerivatives<3>(density, zero, W, w, ruledQuadratic_[f]);
  }
  quadraticAlpha_ = alpha_;
  quadraticBeta_ = beta_;
  quadraticStale_ = false;
  quadraticEveryFace_ = everyFace;
}

namespace {

/// The whole stencil as one 18-dof element energy: the naive nested-Jet reference, with α and β as
/// parameters.
struct BendingStencilEnergy {
  static constexpr int kVertices = 6;
  static constexpr int kParameters = 2;
  static constexpr std::array<const char*, 2> kParameterNames{{"alpha", "beta"}};
  std::array<double, 2> parameters{};
  std::vector<StencilEdges> edges;
  ShellReference ref;
  template <typename T>
  T operator()(const T* x, const T* p, int f) const {
    T b[3];
    stencilSecondFundamentalForm(x, edges[f], b);
    return ref.area[f] *
           bendingDensity(b, ref.secondFundamentalForm[f].data(), ref.inverseMetric[f].data(), p[0], p[1]);
  }
};

}  // namespace

EnergyTermPtr makeBendingTerm(const TriMesh& mesh, const Topology& topology, const ShellReference& reference,
                              double alpha, double beta) {
  return std::make_shared<BendingTerm>(mesh, topology, reference, alpha, beta);
}

EnergyTermPtr makeBendingTermNestedJet(const TriMesh& mesh, const Topology& topology,
                                       const ShellReference& reference, double alpha, double beta) {
  BendingStencilEnergy energy{{{alpha, beta}}, {}, reference};
  energy.edges.resize(static_cast<std::size_t>(mesh.numFaces()));
  for (int f = 0; f < mesh.numFaces(); ++f)
    for (int i = 0; i < 3; ++i) energy.edges[f].boundary[i] = topology.bendingStencil(f, 3 + i) < 0;
  StencilTable table;
  table.width = 6;
  table.ids.assign(topology.bendingStencil.data(), topology.bendingStencil.data() + topology.bendingStencil.size());
  return std::make_shared<ElementEnergyTerm<BendingStencilEnergy>>("bending_nested_jet", std::move(table),
                                                                   mesh.numVertices(), std::move(energy));
}

}  // namespace jetshell
