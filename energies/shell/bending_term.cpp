// Bending term, differentiated in stages.
//
// Data flow per evaluation:
//   pass 1, per face f:  c_f = e0 × e1 -> n_f = unitNormal(c_f); keeps n, ∂n/∂c, ∇²_c n_k and ∂n/∂x_f (3×9).
//   pass 2, per edge e:  m_e = ½(n_A + n_B) -> n̄_e = kelvinInversion(m_e); keeps n̄, ∂n̄/∂m, ∇²_m n̄_k.
//   pass 3, per face f (the 6-vertex stencil): b(e0, e1, n̄0, n̄1, n̄2) (bilinear primitive) -> W_b(b) (the
//     templated density). Gradient = area · J_bᵀ w. Hessian = area · (J_bᵀ W'' J_b [Gauss–Newton part]
//     + Σ_k w_k ∇²b_k [exact only]), the second part by the chain rule through passes 2 and 1.
//   Exact Hessian without projection: between passes 2 and 3, contractCurvature sums each face normal's and
//     mid-edge normal's adjoint over the stencils that share it and contracts its stage Hessians once; pass 3
//     then assembles a face's curvature in its own stencil and an edge's in its first face's (the same sum in
//     other blocks). A projection needs each stencil's own block, so it keeps the per-stencil curvature.
// The nonlinear stages (unitNormal, kelvinInversion, bendingDensity: 3 inputs each) get their derivatives from
// Jet<Jet<double,3>,3> on the AD path and from energies/shell/analytic_stages.h on the analytic path; everything
// else is shared. Boundary edges (energies/shell/edge_rules.h): pass 2 takes m = ½(n + n_ghost(n)) with the
// ghost rule as a 3 → 3 Jet stage; a face with moment-free edges takes the rule's minimized density as its
// pass-3 density stage (Jets on the AD path; the analytic path takes the constant quadratic form that density
// is, once per α, β and rules; the rest of the chain is unchanged). Each face normal serves four
// stencils and each mid-edge normal two, computed once.
#include "energies/shell/bending_term.h"

#include "core/element_loop.h"
#include "core/flatten.h"
#include "core/origin_derivatives.h"
#include "core/parameter_derivatives.h"
#include "energies/shell/analytic_stages.h"
#include "energies/element_energy_term.h"
#include "energies/shell/shell_geometry.h"
#include "energies/shell/shell_terms.h"
#include "core/stage_derivatives.h"

#include <Eigen/Geometry>

#include <array>
#include <cstdint>

namespace jetshell {
namespace {

using Mat3 = Eigen::Matrix3d;
using Vec3 = Eigen::Vector3d;
using Mat39 = Eigen::Matrix<double, 3, 9>;
using Mat3x12 = Eigen::Matrix<double, 3, 12>;
using Mat3x18 = Eigen::Matrix<double, 3, 18>;
using Mat18 = Eigen::Matrix<double, 18, 18>;

/// ∂c/∂x (3×9) for c = (x1 − x0) × (x2 − x0).
Mat39 crossJacobian(const Vec3& e0, const Vec3& e1) {
  Mat39 C;
  C.block<3, 3>(0, 3) = -analytic::crossMatrix(e1);
  C.block<3, 3>(0, 6) = analytic::crossMatrix(e0);
  C.block<3, 3>(0, 0) = -(C.block<3, 3>(0, 3) + C.block<3, 3>(0, 6));
  return C;
}

Vec3 position(const Eigen::VectorXd& x, int v) { return x.segment<3>(3 * v); }

/// Adds scale × a 3×9 block given in a face's own vertex order into stencil-local columns.
template <typename Dst>
void addFaceColumns(Dst& dst, const Mat39& src, const std::int8_t* local, double scale) {
  for (int k = 0; k < 3; ++k) dst.template middleCols<3>(3 * local[k]) += scale * src.middleCols<3>(3 * k);
}

constexpr std::int8_t kSelf[3] = {0, 1, 2};

/// Adds a row over edge i's compact vertices (0, 1, 2, 3+i) into a full 18-column stencil row.
template <typename Row, typename Compact>
void addCompact(Row&& row, const Compact& v, int i) {
  row.template head<9>() += v.template head<9>();
  row.template segment<3>(9 + 3 * i) += v.template tail<3>();
}

/// Adds Jᵀ X J (X symmetric 3×3) to the stencil block H, for the Jacobian J = [J_0, J_1, …, J_{K−1}] (3 × 3K)
/// of a translation-invariant quantity (Σ_k J_k = 0), given by its last K − 1 blocks. Only the blocks among
/// vertices 1..K−1 are products; those of vertex 0 follow from the zero row and column sums. coupling (or
/// null; K = 3): an antisymmetric 3×3 added to the (1, 2) block and its transpose to (2, 1); the vertex-0
/// blocks carry its share the same way. vertex[k]: vertex k's stencil index. upper: only the blocks with
/// vertex[r] <= vertex[c] are added (assembly reads the upper triangle).
template <int K, typename Tail, typename Index>
void addTranslationInvariant(const Tail& tail, const Mat3& X, const Index* vertex, bool upper, Mat18& H,
                             const Mat3* coupling = nullptr) {
  constexpr int T = K - 1;
  const Eigen::Matrix<double, 3, 3 * T> XJ = X.lazyProduct(tail);
  Mat3 B[K][K];
  for (int c = 1; c < K; ++c)
    for (int r = 1; r <= c; ++r)
      B[r][c].noalias() =
          tail.template middleCols<3>(3 * (r - 1)).transpose().lazyProduct(XJ.template middleCols<3>(3 * (c - 1)));
  if (coupling != nullptr) B[1][2] += *coupling;
  for (int c = 1; c < K; ++c)
    for (int r = c + 1; r < K; ++r) B[r][c] = B[c][r].transpose();
  Mat3 corner = Mat3::Zero();
  for (int c = 1; c < K; ++c) {
    B[0][c] = -B[1][c];
    for (int r = 2; r < K; ++r) B[0][c] -= B[r][c];
    B[c][0] = B[0][c].transpose();
    corner -= B[0][c];
  }
  B[0][0] = 0.5 * (corner + corner.transpose());
  for (int r = 0; r < K; ++r)
    for (int c = 0; c < K; ++c)
      if (!upper || vertex[r] <= vertex[c]) H.block<3, 3>(3 * vertex[r], 3 * vertex[c]) += B[r][c];
}

}  // namespace

BendingTerm::BendingTerm(const TriMesh& mesh, const Topology& topo, const ShellReference& ref, double alpha,
                         double beta)
    : F_(mesh.F), topo_(topo), ref_(ref), alpha_(alpha), beta_(beta) {
  const int nf = mesh.numFaces();
  table_.width = 6;
  table_.ids.assign(topo.bendingStencil.data(), topo.bendingStencil.data() + topo.bendingStencil.size());
  schedule_ = scheduleElements(table_, mesh.numVertices());
  neighborLocal_.resize(static_cast<std::size_t>(nf));
  for (int f = 0; f < nf; ++f) {
    for (int i = 0; i < 3; ++i) {
      const int g = topo.faceNeighbors(f, i);
      for (int k = 0; k < 3; ++k) {
        std::int8_t local = static_cast<std::int8_t>(k);  // boundary: the face itself
        if (g >= 0) {
          const int v = mesh.F(g, k);
          local = v == mesh.F(f, (i + 1) % 3)   ? static_cast<std::int8_t>((i + 1) % 3)
                  : v == mesh.F(f, (i + 2) % 3) ? static_cast<std::int8_t>((i + 2) % 3)
                                                : static_cast<std::int8_t>(3 + i);
        }
        neighborLocal_[f][3 * i + k] = local;
      }
    }
  }
  faces_.resize(static_cast<std::size_t>(nf));
  edges_.resize(static_cast<std::size_t>(topo.numEdges()));
  const int ne = topo.numEdges();
  rules_.assign(static_cast<std::size_t>(ne), EdgeRule::PageFree);
  ruleData_.resize(static_cast<std::size_t>(ne));
  ghosts_.resize(static_cast<std::size_t>(ne));
  for (int e = 0; e < ne; ++e) {
    const int f = topo.edgeFaces(e, 0);
    const Vec3 x0 = mesh.V.row(mesh.F(f, 0));
    const Vec3 r = (Vec3(mesh.V.row(mesh.F(f, 1))) - x0).cross(Vec3(mesh.V.row(mesh.F(f, 2))) - x0).normalized();
    for (int c = 0; c < 3; ++c) ruleData_[e].reference[c] = r[c];
  }
  minimized_.assign(static_cast<std::size_t>(nf), {false, false, false});
  restPositions_ = flatten(mesh.V);
  givenForm_ = ref.secondFundamentalForm;
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
  if (staged_) return stagedCurvatureOrigin(xOrigin);
  computeFaceStages(xOrigin, 0, false, false, false);
  computeEdgeStages(0, false, false);
  for (int f = 0; f < static_cast<int>(F_.rows()); ++f) {
    const Vec3 p0 = xOrigin.segment<3>(3 * F_(f, 0));
    const Vec3 e0 = xOrigin.segment<3>(3 * F_(f, 1)) - p0, e1 = xOrigin.segment<3>(3 * F_(f, 2)) - p0;
    const Vec3& n0 = edges_[topo_.faceEdges(f, 0)].nbar;
    const Vec3& n1 = edges_[topo_.faceEdges(f, 1)].nbar;
    const Vec3& n2 = edges_[topo_.faceEdges(f, 2)].nbar;
    ref_.secondFundamentalForm[f] = {2.0 * (n1 - n0).dot(e0), -2.0 * n0.dot(e1), 2.0 * (n2 - n0).dot(e1)};
  }
}

Vec3 BendingTerm::meanNormal(int e, int order) {
  const int fa = topo_.edgeFaces(e, 0), fb = topo_.edgeFaces(e, 1);
  const Vec3& n = faces_[fa].n;
  if (fb >= 0) return 0.5 * (n + faces_[fb].n);
  // A boundary edge: the ghost normal from the edge's rule, differentiated with Jets as a 3 → 3 stage.
  const EdgeRule rule = rules_[e];
  const EdgeRuleData& data = ruleData_[e];
  const auto ghost = [rule, &data](const auto& z) { return ghostNormal(rule, z, data); };
  Vec3 g;
  Mat3 G;
  GhostStage& s = ghosts_[e];
  if (order == 0) {
    const V3<double> v = ghost(V3<double>{{n[0], n[1], n[2]}});
    g = Vec3(v[0], v[1], v[2]);
  } else if (order == 1) {
    vectorStageJacobian(ghost, n, g, G);
  } else {
    vectorStageDerivatives(ghost, n, g, G, s.hessians);
    for (Mat3& h : s.hessians) h *= 0.5;
  }
  if (order > 0) s.dmdn = 0.5 * (Mat3::Identity() + G);
  return 0.5 * (n + g);
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

double BendingTerm::evaluate(const Eigen::VectorXd& x, const EvalRequest& request, const EvalOptions& options) {
    // A Gauss–Newton block Jᵀ W'' J is positive semi-definite by construction (W'' is, for every admissible
    // material and edge rule: the ruled densities are Schur complements of convex quadratics), so it is never
    // projected. Projecting it would cost an eigendecomposition per block for nothing: its rank is 3, so the
    // Cholesky test in edge space (core/psd_projection.h) fails on every one.
    if (options.hessianModel == HessianModel::GaussNewton && options.projection != PsdProjection::None) {
      EvalOptions unprojected = options;
      unprojected.projection = PsdProjection::None;
      return evaluate(x, request, unprojected);
    }
    if (staged_) return evaluateStaged(x, request, options);
    const bool ad = options.path == DerivativePath::AutoDiff;
    const bool exact = options.hessianModel == HessianModel::Exact;
    // Stage order: 0 values, 1 Jacobians, 2 Hessians (only the exact bending Hessian needs them).
    const int order = request.hessian != nullptr && exact ? 2 : request.gradient != nullptr || request.hessian ? 1 : 0;
    if (ad ? request.hessian != nullptr : order > 0) updateRuledQuadratics(ad);
    // Assembly reads the upper triangle of each stencil block; only a projection needs the whole block (and
    // the block of each stencil's own energy: then the shared stages' curvature is not contracted ahead).
    const bool upper = options.projection == PsdProjection::None;
    const bool contracted = upper && order == 2;
    computeFaceStages(x, order, ad, !contracted, request.hessian != nullptr);
    computeEdgeStages(order, ad, !contracted);
    if (contracted) contractCurvature(x, ad);
    return runElementLoop<6>(table_, schedule_, x, request, options.projection, elementEnergy_,
                             [&](int f, const int* ids, bool wantG, bool wantH, Eigen::Matrix<double, 18, 1>& g,
                                 Mat18& H) {
                               return stencil(x, f, ids, wantG, wantH, ad, exact, upper, contracted, g, H);
                             });
  }

void BendingTerm::computeFaceStages(const Eigen::VectorXd& x, int order, bool ad, bool stageHessians,
                                    bool hessian) {
    const int nf = static_cast<int>(F_.rows());
    if (hessian) faceJacobian_.resize(static_cast<std::size_t>(nf));
    if (order == 2 && !stageHessians) order = 1;
    if (order == 2) faceHessian_.resize(static_cast<std::size_t>(nf));
#pragma omp parallel for schedule(static)
    for (int f = 0; f < nf; ++f) {
      const Vec3 x0 = position(x, F_(f, 0));
      const Vec3 e0 = position(x, F_(f, 1)) - x0, e1 = position(x, F_(f, 2)) - x0;
      const Vec3 c = e0.cross(e1);
      FaceStage& s = faces_[f];
      if (order == 0) {
        // The same function the derivative paths differentiate: a zero-area face gives a non-finite energy on
        // every path (Eigen's normalized() would leave c = 0 finite here while the derivatives are NaN).
        const V3<double> v = unitNormal(V3<double>{{c[0], c[1], c[2]}});
        s.n = Vec3(v[0], v[1], v[2]);
        continue;
      }
      const auto stage = [](const auto& z) { return unitNormal(z); };
      if (ad && order == 2) {
        vectorStageDerivatives(stage, c, s.n, s.dndc, faceHessian_[f]);
      } else if (ad) {
        vectorStageJacobian(stage, c, s.n, s.dndc);
      } else if (order == 2) {
        analytic::unitNormal(c, s.n, s.dndc, faceHessian_[f]);
      } else {
        analytic::unitNormal(c, s.n, s.dndc);
      }
      if (hessian) faceJacobian_[f].noalias() = s.dndc.lazyProduct(crossJacobian(e0, e1));
    }
  }

void BendingTerm::computeEdgeStages(int order, bool ad, bool stageHessians) {
    const int ne = topo_.numEdges();
    const int ghostOrder = order;  // the ghost rules' Hessians are small (boundary edges) and always kept
    const bool keepMean = order == 2 && !stageHessians;
    if (keepMean) {
      order = 1;
      edgeMeans_.resize(static_cast<std::size_t>(ne));
    }
    if (order == 2) edgeHessian_.resize(static_cast<std::size_t>(ne));
#pragma omp parallel for schedule(static)
    for (int e = 0; e < ne; ++e) {
      const Vec3 m = meanNormal(e, ghostOrder);
      EdgeStage& s = edges_[e];
      if (keepMean) edgeMeans_[e] = m;
      const auto stage = [](const auto& z) { return kelvinInversion(z); };
      if (order == 0) {
        const V3<double> v = kelvinInversion(V3<double>{{m[0], m[1], m[2]}});
        s.nbar = Vec3(v[0], v[1], v[2]);
      } else if (ad && order == 2) {
        vectorStageDerivatives(stage, m, s.nbar, s.dndm, edgeHessian_[e]);
      } else if (ad) {
        vectorStageJacobian(stage, m, s.nbar, s.dndm);
      } else if (order == 2) {
        analytic::kelvinInversion(m, s.nbar, s.dndm, edgeHessian_[e]);
      } else {
        analytic::kelvinInversion(m, s.nbar, s.dndm);
      }
    }
  }

void BendingTerm::faceDensity(int f, const double* b, bool ad, double& W, Vec3& w, Mat3* Wbb) const {
  const double* B = ref_.secondFundamentalForm[f].data();
  const bool* minimized = minimized_[f].data();
  if (ad) {
    const double* P = ref_.inverseMetric[f].data();
    auto density = [&](const auto* z) { return ruledBendingDensity(z, B, P, alpha_, beta_, minimized); };
    scalarStageGradient<3>(density, b, W, w);
    if (Wbb != nullptr) *Wbb = ruledQuadratic_[static_cast<std::size_t>(f)];
  } else if (minimized[0] || minimized[1] || minimized[2]) {
    const Vec3 d(b[0] - B[0], b[1] - B[1], b[2] - B[2]);
    const Mat3& A = ruledQuadratic_[static_cast<std::size_t>(f)];
    w.noalias() = A * d;
    W = 0.5 * d.dot(w);
    if (Wbb != nullptr) *Wbb = A;
  } else {
    const double d[3] = {b[0] - B[0], b[1] - B[1], b[2] - B[2]};
    if (Wbb != nullptr) {
      analytic::stvkQuadratic(ref_.inverseMetric[f].data(), alpha_, 0.5 * beta_, d, W, w, *Wbb);
    } else {
      analytic::stvkQuadratic(ref_.inverseMetric[f].data(), alpha_, 0.5 * beta_, d, W, w);
    }
  }
}

void BendingTerm::contractCurvature(const Eigen::VectorXd& x, bool ad) {
  const int nf = static_cast<int>(F_.rows()), ne = topo_.numEdges();
  slotAdjoint_.resize(static_cast<std::size_t>(nf));
  meanAdjoint_.resize(static_cast<std::size_t>(ne));
  faceCurvature_.resize(static_cast<std::size_t>(nf));
  edgeCurvature_.resize(static_cast<std::size_t>(ne));
  // Each stencil's adjoint of its three mid-edge normals, ∂(w·b)/∂n̄_i (w = area · ∂W/∂b).
#pragma omp parallel for schedule(static)
  for (int f = 0; f < nf; ++f) {
    const Vec3 p0 = position(x, F_(f, 0));
    const Vec3 e0 = position(x, F_(f, 1)) - p0, e1 = position(x, F_(f, 2)) - p0;
    V3<double> nb[3];
    for (int i = 0; i < 3; ++i) {
      const Vec3& n = edges_[topo_.faceEdges(f, i)].nbar;
      nb[i] = {{n[0], n[1], n[2]}};
    }
    double b[3];  // as in stencil(), to the bit
    secondFundamentalForm(V3<double>{{e0[0], e0[1], e0[2]}}, V3<double>{{e1[0], e1[1], e1[2]}}, nb[0], nb[1],
                          nb[2], b);
    double W;
    Vec3 w;
    faceDensity(f, b, ad, W, w, nullptr);
    w *= energyScale() * ref_.area[f];
    slotAdjoint_[f] = {-2.0 * w[0] * e0 - 2.0 * (w[1] + w[2]) * e1, 2.0 * w[0] * e0, 2.0 * w[2] * e1};
  }
  // Per edge: the total adjoint of n̄ (both stencils), the curvature Σ_k a_k ∇²_m n̄_k and the mean normal's
  // adjoint (∂n̄/∂m)ᵀ a.
#pragma omp parallel for schedule(static)
  for (int e = 0; e < ne; ++e) {
    Vec3 a = Vec3::Zero();
    for (int s = 0; s < 2; ++s) {
      const int f = topo_.edgeFaces(e, s);
      if (f < 0) continue;
      for (int i = 0; i < 3; ++i)
        if (topo_.faceEdges(f, i) == e) a += slotAdjoint_[f][i];
    }
    const EdgeStage& s = edges_[e];
    Vec3 nbar;
    Mat3 dndm;
    StageHessian hs;
    if (ad) {
      vectorStageDerivatives([](const auto& z) { return kelvinInversion(z); }, edgeMeans_[e], nbar, dndm, hs);
    } else {
      analytic::kelvinInversion(edgeMeans_[e], nbar, dndm, hs);
    }
    edgeCurvature_[e] = a[0] * hs[0] + a[1] * hs[1] + a[2] * hs[2];
    meanAdjoint_[e].noalias() = s.dndm.transpose() * a;
  }
  // Per face: the total adjoint h of its normal (½ of each interior edge's mean-normal adjoint, through the rule's
  // ∂m/∂n on a boundary edge), its curvature in c with the ghost rules' own curvature, and the cross product's.
#pragma omp parallel for schedule(static)
  for (int f = 0; f < nf; ++f) {
    Vec3 h = Vec3::Zero();
    Mat3 ghostCurvature = Mat3::Zero();
    bool anyGhost = false;
    for (int i = 0; i < 3; ++i) {
      const int e = topo_.faceEdges(f, i);
      const Vec3& gm = meanAdjoint_[e];
      if (topo_.faceNeighbors(f, i) >= 0) {
        h += 0.5 * gm;
      } else {
        const GhostStage& ghost = ghosts_[e];
        h.noalias() += ghost.dmdn.transpose() * gm;
        ghostCurvature += gm[0] * ghost.hessians[0] + gm[1] * ghost.hessians[1] + gm[2] * ghost.hessians[2];
        anyGhost = true;
      }
    }
    const FaceStage& s = faces_[f];
    // c = e0 × e1 as computeFaceStages takes it, and the unit normal's Hessians there.
    const Vec3 p0 = position(x, F_(f, 0));
    const Vec3 c = (position(x, F_(f, 1)) - p0).cross(position(x, F_(f, 2)) - p0);
    Vec3 n;
    Mat3 dndc;
    StageHessian hs;
    if (ad) {
      vectorStageDerivatives([](const auto& z) { return unitNormal(z); }, c, n, dndc, hs);
    } else {
      analytic::unitNormal(c, n, dndc, hs);
    }
    FaceCurvature& out = faceCurvature_[f];
    out.c = h[0] * hs[0] + h[1] * hs[1] + h[2] * hs[2];
    if (anyGhost) out.c.noalias() += s.dndc.transpose() * ghostCurvature * s.dndc;
    out.q = -analytic::crossMatrix(s.dndc.transpose() * h);
  }
}

JETSHELL_FLATTEN double BendingTerm::stencil(const Eigen::VectorXd& x, int f, const int* ids, bool wantG, bool wantH, bool ad, bool exact,
                 bool upper, bool contracted, Eigen::Matrix<double, 18, 1>& g, Mat18& H) const {
    const Vec3 p0 = position(x, ids[0]);
    const Vec3 e0 = position(x, ids[1]) - p0, e1 = position(x, ids[2]) - p0;
    const EdgeStage* edge[3];
    for (int i = 0; i < 3; ++i) edge[i] = &edges_[topo_.faceEdges(f, i)];
    const V3<double> ve0{{e0[0], e0[1], e0[2]}}, ve1{{e1[0], e1[1], e1[2]}};
    V3<double> nb[3];
    for (int i = 0; i < 3; ++i) nb[i] = {{edge[i]->nbar[0], edge[i]->nbar[1], edge[i]->nbar[2]}};
    double b[3];
    secondFundamentalForm(ve0, ve1, nb[0], nb[1], nb[2], b);
    const double* B = ref_.secondFundamentalForm[f].data();
    const double* P = ref_.inverseMetric[f].data();
    const double area = energyScale() * ref_.area[f];
    // A face with moment-free edges: its density minimized over them (edge_rules.h), on both paths from Jets.
    const bool* minimized = minimized_[f].data();
    if (!wantG && !wantH) return area * ruledBendingDensity(b, B, P, alpha_, beta_, minimized);

    double W;
    Vec3 w;
    Mat3 Wbb;
    faceDensity(f, b, ad, W, w, wantH ? &Wbb : nullptr);

    const std::int8_t* nloc = neighborLocal_[f].data();
    const int fn[3] = {topo_.faceNeighbors(f, 0), topo_.faceNeighbors(f, 1), topo_.faceNeighbors(f, 2)};
    if (!wantH) {
      gradientByAdjoints(x, f, ids, e0, e1, area * w, nloc, fn, g);
      return area * W;
    }
    // M_i = ∂m_i/∂x and N_i = ∂n̄_i/∂x, compact over edge i's four stencil vertices (0, 1, 2, 3+i): 3×12.
    // ∂n/∂x of this face (0) and the neighbours (1..3) from the face pass, and ∂c/∂x where the curvature needs
    // it (this face's when contracted, all four otherwise), each in its face's own vertex order.
    Mat39 C[4];
    const Mat39* dndx[4] = {&faceJacobian_[f], nullptr, nullptr, nullptr};
    if (exact) C[0] = crossJacobian(e0, e1);
    for (int i = 0; i < 3; ++i) {
      if (fn[i] < 0) continue;
      dndx[1 + i] = &faceJacobian_[fn[i]];
      if (!exact || contracted) continue;
      const std::int8_t* local = nloc + 3 * i;
      const Vec3 q0 = position(x, ids[local[0]]);
      C[1 + i] = crossJacobian(position(x, ids[local[1]]) - q0, position(x, ids[local[2]]) - q0);
    }
    Mat3x12 M[3], N[3];
    for (int i = 0; i < 3; ++i) {
      M[i].leftCols<9>() = 0.5 * *dndx[0];
      M[i].rightCols<3>().setZero();
      if (fn[i] >= 0) {
        const Mat39& dn = *dndx[1 + i];
        for (int k = 0; k < 3; ++k) {
          const int c = nloc[3 * i + k] < 3 ? nloc[3 * i + k] : 3;
          M[i].middleCols<3>(3 * c) += 0.5 * dn.middleCols<3>(3 * k);
        }
      } else {
        // A boundary edge: m = ½(n + n_ghost(n)), ∂m/∂n from the rule's stage.
        M[i].leftCols<9>() = ghosts_[topo_.faceEdges(f, i)].dmdn.lazyProduct(*dndx[0]);
      }
      N[i] = edge[i]->dndm.lazyProduct(M[i]);
    }
    const Vec3& n0 = edge[0]->nbar;
    const Vec3& n1 = edge[1]->nbar;
    const Vec3& n2 = edge[2]->nbar;
    // J_b (3×18): b00 = 2(n̄1 − n̄0)·e0, b01 = −2 n̄0·e1, b11 = 2(n̄2 − n̄0)·e1; e0 = x1 − x0, e1 = x2 − x0.
    Mat3x18 Jb = Mat3x18::Zero();
    addCompact(Jb.row(0), 2.0 * e0.transpose().lazyProduct(N[1]), 1);
    addCompact(Jb.row(0), -2.0 * e0.transpose().lazyProduct(N[0]), 0);
    addCompact(Jb.row(1), -2.0 * e1.transpose().lazyProduct(N[0]), 0);
    addCompact(Jb.row(2), 2.0 * e1.transpose().lazyProduct(N[2]), 2);
    addCompact(Jb.row(2), -2.0 * e1.transpose().lazyProduct(N[0]), 0);
    const Vec3 d0 = 2.0 * (n1 - n0), d1 = -2.0 * n0, d2 = 2.0 * (n2 - n0);
    Jb.block<1, 3>(0, 3) += d0.transpose();
    Jb.block<1, 3>(0, 0) -= d0.transpose();
    Jb.block<1, 3>(1, 6) += d1.transpose();
    Jb.block<1, 3>(1, 0) -= d1.transpose();
    Jb.block<1, 3>(2, 6) += d2.transpose();
    Jb.block<1, 3>(2, 0) -= d2.transpose();

    w *= area;
    if (wantG) g.noalias() = Jb.transpose().lazyProduct(w);
    if (!wantH) return area * W;

    const Mat3x18 WJ = (area * Wbb).lazyProduct(Jb);
    if (upper) {
      for (int c = 0; c < 6; ++c)
        for (int r = 0; r <= c; ++r)
          H.block<3, 3>(3 * r, 3 * c).noalias() = Jb.middleCols<3>(3 * r).transpose().lazyProduct(WJ.middleCols<3>(3 * c));
    } else {
      H.noalias() = Jb.transpose().lazyProduct(WJ);
    }
    if (exact) addCurvatureOfB(f, contracted, e0, e1, w, M, N, nloc, fn, C, upper, H);
    return area * W;
  }

void BendingTerm::gradientByAdjoints(const Eigen::VectorXd& x, int f, const int* ids, const Vec3& e0, const Vec3& e1,
                                     const Vec3& w, const std::int8_t* nloc, const int* fn,
                                     Eigen::Matrix<double, 18, 1>& g) const {
  // g = J_bᵀ w without forming J_b: the adjoint of b flows back to the mid-edge normals, the mean normals, the
  // face normals and the positions (the same chain as the Jacobians in stencil(), taken the other way).
  g.setZero();
  const Vec3& n0 = edges_[topo_.faceEdges(f, 0)].nbar;
  const Vec3& n1 = edges_[topo_.faceEdges(f, 1)].nbar;
  const Vec3& n2 = edges_[topo_.faceEdges(f, 2)].nbar;
  // b00 = 2(n̄1 − n̄0)·e0, b01 = −2 n̄0·e1, b11 = 2(n̄2 − n̄0)·e1: their explicit dependence on e0 and e1 ...
  const Vec3 d0 = (2.0 * w[0]) * (n1 - n0), d12 = (-2.0 * w[1]) * n0 + (2.0 * w[2]) * (n2 - n0);
  g.segment<3>(3) += d0;
  g.segment<3>(6) += d12;
  g.segment<3>(0) -= d0 + d12;
  // ... and the adjoints of the mid-edge normals n̄_i.
  const Vec3 u[3] = {-2.0 * (w[0] * e0 + (w[1] + w[2]) * e1), 2.0 * w[0] * e0, 2.0 * w[2] * e1};
  // The adjoint of c = (x1 − x0) × (x2 − x0) added to the face's vertices (stencil slots `slot`).
  auto addCross = [&g](const Vec3& a, const Vec3& b, const Vec3& y, const std::int8_t* slot) {
    const Vec3 g1 = b.cross(y), g2 = y.cross(a);
    g.segment<3>(3 * slot[1]) += g1;
    g.segment<3>(3 * slot[2]) += g2;
    g.segment<3>(3 * slot[0]) -= g1 + g2;
  };
  Vec3 face = Vec3::Zero();  // the adjoint of this face's normal
  for (int i = 0; i < 3; ++i) {
    const int e = topo_.faceEdges(f, i);
    const Vec3 m = edges_[e].dndm.transpose() * u[i];  // the adjoint of the mean normal m_i
    if (fn[i] < 0) {
      face.noalias() += ghosts_[e].dmdn.transpose() * m;  // m = ½(n + n_ghost(n))
      continue;
    }
    face += 0.5 * m;
    const std::int8_t* local = nloc + 3 * i;
    const Vec3 q0 = position(x, ids[local[0]]);
    addCross(position(x, ids[local[1]]) - q0, position(x, ids[local[2]]) - q0,
             faces_[fn[i]].dndc.transpose() * (0.5 * m), local);
  }
  addCross(e0, e1, faces_[f].dndc.transpose() * face, kSelf);
}

void BendingTerm::addCurvatureOfB(int f, bool contracted, const Vec3& e0, const Vec3& e1,
                                  const Vec3& w, const Mat3x12* M, const Mat3x12* N, const std::int8_t* nloc,
                                  const int* fn, const Mat39* crossJacobians, bool upper, Mat18& H) const {
    // s = w·b = Σ c_ai e_a·n̄_i with c_00 = −2w0, c_01 = 2w0, c_10 = −2(w1 + w2), c_12 = 2w2.
    // The e–n̄ coupling: E_aᵀ R_a + R_aᵀ E_a with R_a = Σ_i c_ai N_i, e0 = x1 − x0, e1 = x2 − x0.
    Mat3x18 R0 = Mat3x18::Zero(), R1 = Mat3x18::Zero();
    for (int r = 0; r < 3; ++r) {
      addCompact(R0.row(r), 2.0 * w[0] * N[1].row(r), 1);
      addCompact(R0.row(r), -2.0 * w[0] * N[0].row(r), 0);
      addCompact(R1.row(r), -2.0 * (w[1] + w[2]) * N[0].row(r), 0);
      addCompact(R1.row(r), 2.0 * w[2] * N[2].row(r), 2);
    }
    const Mat3x18 R01 = R0 + R1;
    if (upper) {
      // Row block b gets R (its columns c >= b), and column block b gets Rᵀ (its rows c <= b).
      const Mat3x18* R[3] = {&R01, &R0, &R1};
      const double sign[3] = {-1.0, 1.0, 1.0};
      for (int b = 0; b < 3; ++b)
        for (int c = 0; c < 6; ++c) {
          if (c >= b) H.block<3, 3>(3 * b, 3 * c) += sign[b] * R[b]->middleCols<3>(3 * c);
          if (c <= b) H.block<3, 3>(3 * c, 3 * b) += sign[b] * R[b]->middleCols<3>(3 * c).transpose();
        }
    } else {
      H.middleRows<3>(3) += R0;
      H.middleRows<3>(6) += R1;
      H.middleRows<3>(0) -= R01;
      H.middleCols<3>(3) += R0.transpose();
      H.middleCols<3>(6) += R1.transpose();
      H.middleCols<3>(0) -= R01.transpose();
    }

    if (contracted) {
      // The shared stages' curvature, contracted ahead with their total adjoints: this face's own, and that of
      // the edges this stencil owns.
      for (int i = 0; i < 3; ++i) {
        const int e = topo_.faceEdges(f, i);
        if (topo_.edgeFaces(e, 0) != f) continue;
        const int vertex[4] = {0, 1, 2, 3 + i};
        addTranslationInvariant<4>(M[i].rightCols<9>(), edgeCurvature_[e], vertex, upper, H);
      }
      const FaceCurvature& fc = faceCurvature_[f];
      addTranslationInvariant<3>(crossJacobians[0].rightCols<6>(), fc.c, kSelf, upper, H, &fc.q);
      return;
    }
    const Vec3 gnb[3] = {-2.0 * w[0] * e0 - 2.0 * (w[1] + w[2]) * e1, 2.0 * w[0] * e0, 2.0 * w[2] * e1};
    Vec3 hFace[4] = {Vec3::Zero(), Vec3::Zero(), Vec3::Zero(), Vec3::Zero()};  // this face, neighbours 0..2
    Mat3 ghostCurvature = Mat3::Zero();  // Σ_k (∂s/∂m)_k ∇²_n m_k over boundary edges (nonlinear rules)
    bool anyGhost = false;
    for (int i = 0; i < 3; ++i) {
      const int e = topo_.faceEdges(f, i);
      const EdgeStage& s = edges_[e];
      const StageHessian& hs = edgeHessian_[e];
      const Mat3 Hm = gnb[i][0] * hs[0] + gnb[i][1] * hs[1] + gnb[i][2] * hs[2];
      const int vertex[4] = {0, 1, 2, 3 + i};  // edge i's compact vertices in the stencil
      addTranslationInvariant<4>(M[i].rightCols<9>(), Hm, vertex, upper, H);
      const Vec3 gm = s.dndm.transpose() * gnb[i];
      if (fn[i] >= 0) {
        hFace[0] += 0.5 * gm;
        hFace[1 + i] += 0.5 * gm;
      } else {
        const GhostStage& ghost = ghosts_[e];
        hFace[0] += ghost.dmdn.transpose() * gm;
        ghostCurvature += gm[0] * ghost.hessians[0] + gm[1] * ghost.hessians[1] + gm[2] * ghost.hessians[2];
        anyGhost = true;
      }
    }
    for (int j = 0; j < 4; ++j) {
      if (j > 0 && fn[j - 1] < 0) continue;
      const int face = j == 0 ? f : fn[j - 1];
      const std::int8_t* local = j == 0 ? kSelf : nloc + 3 * (j - 1);
      const FaceStage& s = faces_[face];
      const StageHessian& hs = faceHessian_[face];
      const Vec3& h = hFace[j];
      Mat3 Hc = h[0] * hs[0] + h[1] * hs[1] + h[2] * hs[2];
      // The ghost rules' curvature, Dᵀ G D with D = (∂n/∂c) C, joins the curvature in c.
      if (j == 0 && anyGhost) Hc.noalias() += s.dndc.transpose() * ghostCurvature * s.dndc;
      // k·c = k·(e0 × e1) = e0ᵀ Q e1 with Q = −[k]×, k = (∂n/∂c)ᵀ h: the (x1, x2) block gets Q; Q is
      // antisymmetric, so the blocks of x0 that translation invariance gives carry its share.
      const Mat3 Q = -analytic::crossMatrix(s.dndc.transpose() * h);
      addTranslationInvariant<3>(crossJacobians[j].rightCols<6>(), Hc, local, upper, H, &Q);
    }
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
