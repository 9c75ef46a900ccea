// Membrane term: per face, x (9) -> e0, e1 (linear) -> a = [e_a·e_b] (bilinear primitive) -> W_m(a) (the
// templated density, differentiated with Jet<Jet<double,3>,3> on the AD path, by hand on the analytic path).
#include "energies/shell/membrane_term.h"

#include "core/element_loop.h"
#include "core/origin_derivatives.h"
#include "core/parameter_derivatives.h"
#include "energies/shell/analytic_stages.h"
#include "energies/shell/membrane_projection.h"
#include "energies/shell/shell_geometry.h"
#include "energies/shell/shell_terms.h"
#include "core/stage_derivatives.h"

namespace jetshell {

MembraneTerm::MembraneTerm(const TriMesh& mesh, const ShellReference& ref, double lambda, double mu)
    : ref_(ref), lambda_(lambda), mu_(mu) {
  table_.width = 3;
  table_.ids.assign(mesh.F.data(), mesh.F.data() + mesh.F.size());
  schedule_ = scheduleElements(table_, mesh.numVertices());
  numVertices_ = mesh.numVertices();
}

void MembraneTerm::setStaged(bool staged) {
  staged_ = staged;
  if (!staged || graph_) return;
  graph_ = std::make_unique<Graph>(numVertices_);
  graph_->setElements(table_);
  for (int f = 0; f < table_.size(); ++f) {
    const int* v = table_.element(f);
    graph_->setInputs<0>(f, {difference(v[0], v[1]), difference(v[0], v[2])});
    graph_->setInputs<1>(f, {node(f)});
  }
  graph_->finalize();
  graphEvaluator_ = std::make_unique<StageGraphEvaluator<Graph>>(*graph_);
}

void MembraneTerm::bindStages() {
  MembraneDensityStage& density = graph_->stage<1>();
  density.ref = &ref_;
  density.lambda = lambda_;
  density.mu = mu_;
  density.scale = energyScale();
}

double MembraneTerm::evaluate(const Eigen::VectorXd& x, const EvalRequest& request, const EvalOptions& options) {
  if (staged_) {
    bindStages();
    EvalOptions exact = options;  // the Gauss-Newton option is the bending term's; the membrane stays exact
    exact.hessianModel = HessianModel::Exact;
    return graphEvaluator_->evaluate(x, request, exact, schedule_, elementEnergy_);
  }
  const bool ad = options.path == DerivativePath::AutoDiff;
  if (ad && request.hessian != nullptr) updateDensityHessians();
  // The element projects its own block (energies/shell/membrane_projection.h), so the loop projects nothing.
  const PsdProjection projection = options.projection;
  return runElementLoop<3>(table_, schedule_, x, request, PsdProjection::None, elementEnergy_,
                           [&](int f, const int* ids, bool wantG, bool wantH, Eigen::Matrix<double, 9, 1>& g,
                               Eigen::Matrix<double, 9, 9>& H) {
                             return element(x, f, ids, wantG, wantH, ad, projection, g, H);
                           });
}

void MembraneTerm::setStrainOrigin(const Eigen::VectorXd& xOrigin, double scale) {
  if (staged_) {
    // The metric at the origin from the very stage evaluate() runs, so that ε vanishes there to the bit.
    bindStages();
    graphEvaluator_->localValues<0>(xOrigin, [&](int f, const double* a) {
      ref_.metric[static_cast<std::size_t>(f)] = {a[0], a[1], a[2]};
    });
  } else {
    for (std::size_t f = 0; f < ref_.metric.size(); ++f) {
      const int* ids = table_.element(static_cast<int>(f));
      const Eigen::Vector3d x0 = xOrigin.segment<3>(3 * ids[0]);
      const Eigen::Vector3d e0 = xOrigin.segment<3>(3 * ids[1]) - x0, e1 = xOrigin.segment<3>(3 * ids[2]) - x0;
      ref_.metric[f] = {e0.dot(e0), e0.dot(e1), e1.dot(e1)};
    }
  }
  origin_ = xOrigin;
  scale_ = scale;
  originMoved_ = true;
}

double MembraneTerm::element(const Eigen::VectorXd& x, int f, const int* ids, bool wantG, bool wantH, bool ad,
                             PsdProjection projection, Eigen::Matrix<double, 9, 1>& g,
                             Eigen::Matrix<double, 9, 9>& H) const {
    const Eigen::Vector3d x0 = x.segment<3>(3 * ids[0]), x1 = x.segment<3>(3 * ids[1]), x2 = x.segment<3>(3 * ids[2]);
    const Eigen::Vector3d e0 = x1 - x0, e1 = x2 - x0;
    const double a[3] = {e0.dot(e0), e0.dot(e1), e1.dot(e1)};
    const double* A = ref_.metric[f].data();
    const double* P = ref_.inverseMetric[f].data();
    const double area = energyScale() * ref_.area[f];
    if (!wantG && !wantH) return area * membraneDensity(a, A, P, lambda_, mu_);

    double W;
    Eigen::Vector3d w;
    Eigen::Matrix3d Waa;
    if (ad) {
      auto density = [&](const auto* z) { return membraneDensity(z, A, P, lambda_, mu_); };
      scalarStageGradient<3>(density, a, W, w);
      if (wantH) Waa = densityHessian_[static_cast<std::size_t>(f)];
    } else {
      const double d[3] = {a[0] - A[0], a[1] - A[1], a[2] - A[2]};
      analytic::stvkQuadratic(P, 0.25 * lambda_, 0.25 * mu_, d, W, w, Waa);
    }
    // ∂a/∂e (3×6): a00 -> (2e0, 0), a01 -> (e1, e0), a11 -> (0, 2e1).
    Eigen::Matrix<double, 3, 6> Ja;
    Ja << 2.0 * e0.transpose(), Eigen::RowVector3d::Zero(), e1.transpose(), e0.transpose(),
        Eigen::RowVector3d::Zero(), 2.0 * e1.transpose();
    const Eigen::Matrix<double, 6, 1> ge = Ja.transpose() * w;
    g.segment<3>(3) = area * ge.head<3>();
    g.segment<3>(6) = area * ge.tail<3>();
    g.head<3>() = -(g.segment<3>(3) + g.segment<3>(6));
    if (wantH) {
      Eigen::Matrix<double, 6, 6> He = Ja.transpose() * Waa * Ja;
      He.topLeftCorner<3, 3>().diagonal().array() += 2.0 * w[0];
      He.bottomRightCorner<3, 3>().diagonal().array() += 2.0 * w[2];
      He.topRightCorner<3, 3>().diagonal().array() += w[1];
      He.bottomLeftCorner<3, 3>().diagonal().array() += w[1];
      He *= area;
      const MembraneProjection projected = projectMembraneEdgeBlock(He, e0, e1, projection);
      // e0 = x1 − x0, e1 = x2 − x0: H_x = Lᵀ H_e L.
      H.block<6, 6>(3, 3) = He;
      for (int j = 0; j < 2; ++j) {
        const Eigen::Matrix3d s = -(He.block<3, 3>(0, 3 * j) + He.block<3, 3>(3, 3 * j));
        H.block<3, 3>(0, 3 + 3 * j) = s;
        H.block<3, 3>(3 + 3 * j, 0) = s.transpose();
      }
      H.block<3, 3>(0, 0) = -(H.block<3, 3>(0, 3) + H.block<3, 3>(0, 6));
      if (projected == MembraneProjection::Degenerate) projectPsd<9>(H, projection);
    }
  return area * W;
}

void MembraneTerm::updateDensityHessians() {
  const std::size_t nf = ref_.inverseMetric.size();
  if (densityHessian_.size() == nf && hessianLambda_ == lambda_ && hessianMu_ == mu_) return;
  densityHessian_.resize(nf);
  const double zero[3] = {0.0, 0.0, 0.0};
  for (std::size_t f = 0; f < nf; ++f) {
    const double* P = ref_.inverseMetric[f].data();
    auto density = [&](const auto* z) { return membraneDensity(z, zero, P, lambda_, mu_); };
    double W;
    Eigen::Vector3d w;
    scalarStageDerivatives<3>(density, zero, W, w, densityHessian_[f]);
  }
  hessianLambda_ = lambda_;
  hessianMu_ = mu_;
}

void MembraneTerm::makeStiffnessDamping(double betaR) {
  if (!(std::isfinite(betaR) && betaR > 0.0)) throw InputError(name_ + ": beta_R must be finite and > 0");
  dampingReference_ = dampingValue_ = betaR;
}

std::vector<std::string> MembraneTerm::parameterNames() const {
  if (dampingReference_ > 0.0) return {"beta_R", "lambda", "mu"};
  return {"lambda", "mu"};
}

std::vector<double> MembraneTerm::parameterValues() const {
  if (dampingReference_ > 0.0) return {dampingValue_, lambda_, mu_};
  return {lambda_, mu_};
}

void MembraneTerm::setParameterValues(const std::vector<double>& values) {
  validateParameterValues(name_, parameterNames(), values);
  const std::size_t k = dampingReference_ > 0.0 ? 1 : 0;
  if (k == 1) dampingValue_ = values[0];
  lambda_ = values[k];
  mu_ = values[k + 1];
}

void MembraneTerm::evaluateParameterDerivatives(const Eigen::VectorXd& x, ParameterDerivatives& out) {
  // The face's energy as a function of positions and parameters (the templated geometry and density the
  // stages differentiate); duals seeded on the parameters give ∂E/∂p and ∂²E/∂x∂p.
  auto energy = [&](const auto* xe, const auto* p, int f) {
    using T = std::remove_const_t<std::remove_pointer_t<decltype(xe)>>;
    const V3<T> x0 = load3(xe);
    T a[3];
    metric(load3(xe + 3) - x0, load3(xe + 6) - x0, a);
    const double* A = ref_.metric[f].data();
    const double* P = ref_.inverseMetric[f].data();
    if (dampingReference_ > 0.0)
      return constant<T>(scale_ * ref_.area[f] / dampingReference_) * p[0] * membraneDensity(a, A, P, p[1], p[2]);
    return constant<T>(scale_ * ref_.area[f]) * membraneDensity(a, A, P, p[0], p[1]);
  };
  const std::vector<double> p = parameterValues();
  resetParameterDerivatives(out, x.size(), static_cast<int>(p.size()));
  if (dampingReference_ > 0.0) {
    addParameterDerivatives<3, 3>(table_, x, p.data(), energy, out);
  } else {
    addParameterDerivatives<3, 2>(table_, x, p.data(), energy, out);
  }
}

Eigen::MatrixXd MembraneTerm::originCrossDerivatives(const Eigen::VectorXd& x, const Eigen::MatrixXd& S) const {
  Eigen::MatrixXd out = Eigen::MatrixXd::Zero(x.size(), S.cols());
  if (!originMoved_ || S.cols() == 0) return out;
  // scale · area · W_m(ε) with ε = ½(a(x) − a(y)): the metric difference is passed as a with a zero origin.
  const double zero[3] = {0.0, 0.0, 0.0};
  const double s = energyScale();
  auto energy = [&](const auto* xe, const auto* ye, int f) {
    using T = std::remove_const_t<std::remove_pointer_t<decltype(xe)>>;
    T a[3], b[3];
    metric(load3(xe + 3) - load3(xe), load3(xe + 6) - load3(xe), a);
    metric(load3(ye + 3) - load3(ye), load3(ye + 6) - load3(ye), b);
    const T d[3] = {a[0] - b[0], a[1] - b[1], a[2] - b[2]};
    return constant<T>(s * ref_.area[f]) * membraneDensity(d, zero, ref_.inverseMetric[f].data(), lambda_, mu_);
  };
  addOriginCrossDerivatives<3>(table_, x, origin_, S, energy, out);
  return out;
}

EnergyTermPtr makeMembraneTerm(const TriMesh& mesh, const ShellReference& reference, double lambda, double mu) {
  return std::make_shared<MembraneTerm>(mesh, reference, lambda, mu);
}

}  // namespace jetshell
