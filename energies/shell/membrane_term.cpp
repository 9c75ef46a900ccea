// Membrane term: per face, x (9) -> e0, e1 (linear) -> a = [e_a·e_b] (the metric stage) -> W_m(a) (the density
// stage), the two stages chained by the framework (core/stage.h, ComposedStage).
#include "energies/shell/membrane_term.h"

#include "core/element_loop.h"
#include "core/origin_derivatives.h"
#include "core/parameter_derivatives.h"
#include "core/stage_derivatives.h"
#include "energies/shell/membrane_projection.h"
#include "energies/shell/shell_geometry.h"
#include "energies/shell/shell_terms.h"

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
  // The graph's elements are translation invariant, so a block reaches the projector over (e0, e1): the split
  // into in-plane and normal parts applies as in the per-face element.
  graphEvaluator_->setElementProjector([](const Eigen::VectorXd& x, int, const int* ids, Eigen::Matrix<double, 6, 6>& He,
                                          PsdProjection mode) {
    const Eigen::Vector3d x0 = x.segment<3>(3 * ids[0]);
    return projectMembraneEdgeBlock(He, x.segment<3>(3 * ids[1]) - x0, x.segment<3>(3 * ids[2]) - x0, mode) !=
           MembraneProjection::Degenerate;
  });
}

namespace {

/// Points a density stage at the term's reference, current parameters and kept quadratics (null: none).
void bindDensity(MembraneDensityStage& density, const ShellReference& ref, double lambda, double mu, double scale,
                 const std::vector<Eigen::Matrix3d>* quadratic = nullptr) {
  density.ref = &ref;
  density.lambda = lambda;
  density.mu = mu;
  density.scale = scale;
  density.quadratic = quadratic;
}

}  // namespace

void MembraneTerm::bindStages(bool quadratic) {
  bindDensity(graph_->stage<1>(), ref_, lambda_, mu_, energyScale(), quadratic ? &quadratic_ : nullptr);
}

void MembraneTerm::updateQuadratics() {
  if (quadraticKept_ && quadraticLambda_ == lambda_ && quadraticMu_ == mu_) return;
  const std::size_t nf = ref_.inverseMetric.size();
  quadratic_.resize(nf);
  const double zero[3] = {0.0, 0.0, 0.0};
  for (std::size_t f = 0; f < nf; ++f) {
    const double* P = ref_.inverseMetric[f].data();
    auto density = [&](const auto* a) { return membraneDensity(a, zero, P, lambda_, mu_); };
    double W;
    Eigen::Vector3d w;
    scalarStageDerivatives<3>(density, zero, W, w, quadratic_[f]);
  }
  quadraticLambda_ = lambda_;
  quadraticMu_ = mu_;
  quadraticKept_ = true;
}

double MembraneTerm::evaluate(const Eigen::VectorXd& x, const EvalRequest& request, const EvalOptions& options) {
  // On the Jets, a Hessian takes each face's density Hessian from the kept quadratics.
  const bool quadratic = options.path == DerivativePath::AutoDiff && request.hessian != nullptr;
  if (quadratic) updateQuadratics();
  if (staged_) {
    bindStages(quadratic);
    EvalOptions exact = options;  // the Gauss-Newton option is the bending term's; the membrane stays exact
    exact.hessianModel = HessianModel::Exact;
    return graphEvaluator_->evaluate(x, request, exact, schedule_, elementEnergy_);
  }
  bindDensity(energy_.outer, ref_, lambda_, mu_, energyScale(), quadratic ? &quadratic_ : nullptr);
  // The element projects its own block (energies/shell/membrane_projection.h), so the loop projects nothing.
  const PsdProjection projection = options.projection;
  return runElementLoop<3>(table_, schedule_, x, request, PsdProjection::None, elementEnergy_,
                           [&](int f, const int* ids, bool wantG, bool wantH, Eigen::Matrix<double, 9, 1>& g,
                               Eigen::Matrix<double, 9, 9>& H) {
                             return element(x, f, ids, wantG, wantH, options.path, projection, g, H);
                           });
}

void MembraneTerm::setStrainOrigin(const Eigen::VectorXd& xOrigin, double scale) {
  if (staged_) {
    // The metric at the origin from the very stage evaluate() runs, so that ε vanishes there: to the bit without
    // fused multiply-adds, to round-off with them (-march=native; StageGraphEvaluator::localValues).
    bindStages();
    graphEvaluator_->localValues<0>(xOrigin, [&](int f, const double* a) {
      ref_.metric[static_cast<std::size_t>(f)] = {a[0], a[1], a[2]};
    });
  } else {
    // The metric stage element() differentiates, so that ε vanishes at the origin there too (to the bit without
    // fused multiply-adds, to round-off with them).
    for (std::size_t f = 0; f < ref_.metric.size(); ++f) {
      const int* ids = table_.element(static_cast<int>(f));
      const Eigen::Vector3d x0 = xOrigin.segment<3>(3 * ids[0]);
      const Eigen::Vector3d e0 = xOrigin.segment<3>(3 * ids[1]) - x0, e1 = xOrigin.segment<3>(3 * ids[2]) - x0;
      const double z[6] = {e0[0], e0[1], e0[2], e1[0], e1[1], e1[2]};
      energy_.inner(z, ref_.metric[f].data(), static_cast<int>(f));
    }
  }
  origin_ = xOrigin;
  scale_ = scale;
  originMoved_ = true;
}

double MembraneTerm::element(const Eigen::VectorXd& x, int f, const int* ids, bool wantG, bool wantH,
                             DerivativePath path, PsdProjection projection, Eigen::Matrix<double, 9, 1>& g,
                             Eigen::Matrix<double, 9, 9>& H) const {
  const Eigen::Vector3d x0 = x.segment<3>(3 * ids[0]);
  const Eigen::Vector3d e0 = x.segment<3>(3 * ids[1]) - x0, e1 = x.segment<3>(3 * ids[2]) - x0;
  const double z[6] = {e0[0], e0[1], e0[2], e1[0], e1[1], e1[2]};
  if (!wantG && !wantH) {
    double W;
    energy_(z, &W, f);
    return W;
  }
  // The face's energy as one stage of its edge vectors, metric then density, chained by the framework
  // (core/stage.h, ComposedStage): the gradient and Hessian over (e0, e1), then over the three vertices.
  StageDerivativesOf<EnergyStage> d;
  evaluateStage(energy_, z, f, wantH ? 2 : 1, path, d);
  g.tail<6>() = d.jacobian.transpose();
  g.head<3>() = -(g.segment<3>(3) + g.segment<3>(6));
  if (wantH) {
    Eigen::Matrix<double, 6, 6> He = d.hessians[0];
    const MembraneProjection projected = projectMembraneEdgeBlock(He, e0, e1, projection);
    H.bottomRightCorner<6, 6>() = He;
    completeTranslationInvariant(H);
    if (projected == MembraneProjection::Degenerate) projectPsd<9>(H, projection);
  }
  return d.value[0];
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
      return (scale_ * ref_.area[f] / dampingReference_) * p[0] * membraneDensity(a, A, P, p[1], p[2]);
    return (scale_ * ref_.area[f]) * membraneDensity(a, A, P, p[0], p[1]);
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
    return (s * ref_.area[f]) * membraneDensity(d, zero, ref_.inverseMetric[f].data(), lambda_, mu_);
  };
  addOriginCrossDerivatives<3>(table_, x, origin_, S, energy, out);
  return out;
}

EnergyTermPtr makeMembraneTerm(const TriMesh& mesh, const ShellReference& reference, double lambda, double mu) {
  return std::make_shared<MembraneTerm>(mesh, reference, lambda, mu);
}

}  // namespace jetshell
