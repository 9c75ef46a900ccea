// Membrane term: per face, x (9) -> e0, e1 (linear) -> a = [e_a·e_b] (bilinear primitive) -> W_m(a) (the
// templated density, differentiated with Jet<Jet<double,3>,3> on the AD path, by hand on the analytic path).
#include "energies/shell/membrane_term.h"

#include "core/element_loop.h"
#include "core/parameter_derivatives.h"
#include "energies/shell/analytic_stages.h"
#include "energies/shell/shell_geometry.h"
#include "energies/shell/shell_terms.h"
#include "core/stage_derivatives.h"

#include <cmath>

namespace jetshell {

MembraneTerm::MembraneTerm(const TriMesh& mesh, const ShellReference& ref, double lambda, double mu)
    : ref_(ref), lambda_(lambda), mu_(mu) {
  table_.width = 3;
  table_.ids.assign(mesh.F.data(), mesh.F.data() + mesh.F.size());
  schedule_ = scheduleElements(table_, mesh.numVertices());
}

double MembraneTerm::evaluate(const Eigen::VectorXd& x, const EvalRequest& request, const EvalOptions& options) {
  const bool ad = options.path == DerivativePath::AutoDiff;
  // Clamp on the analytic path: the element clamps its stress term itself (see the header), no 9×9 projection.
  const bool clampStress = !ad && options.projection == PsdProjection::Clamp;
  return runElementLoop<3>(table_, schedule_, x, request, clampStress ? PsdProjection::None : options.projection,
                           elementEnergy_,
                           [&](int f, const int* ids, bool wantG, bool wantH, Eigen::Matrix<double, 9, 1>& g,
                               Eigen::Matrix<double, 9, 9>& H) {
                             return element(x, f, ids, wantG, wantH, ad, clampStress, g, H);
                           });
}

void MembraneTerm::setStrainOrigin(const Eigen::VectorXd& xOrigin, double scale) {
  for (std::size_t f = 0; f < ref_.metric.size(); ++f) {
    const int* ids = table_.element(static_cast<int>(f));
    const Eigen::Vector3d x0 = xOrigin.segment<3>(3 * ids[0]);
    const Eigen::Vector3d e0 = xOrigin.segment<3>(3 * ids[1]) - x0, e1 = xOrigin.segment<3>(3 * ids[2]) - x0;
    ref_.metric[f] = {e0.dot(e0), e0.dot(e1), e1.dot(e1)};
  }
  scale_ = scale;
  originMoved_ = true;
}

double MembraneTerm::element(const Eigen::VectorXd& x, int f, const int* ids, bool wantG, bool wantH, bool ad,
                             bool clampStress, Eigen::Matrix<double, 9, 1>& g, Eigen::Matrix<double, 9, 9>& H) const {
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
      scalarStageDerivatives<3>(density, a, W, w, Waa);
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
      // The stress term S ⊗ I₃, S = [[2w0, w1], [w1, 2w2]] = ∂²a/∂e² contracted with w.
      double s00 = 2.0 * w[0], s01 = w[1], s11 = 2.0 * w[2];
      if (clampStress) {
        // S's eigenvalues, closed form; negative ones set to zero: S₊ = Σ max(σ_k, 0) v_k v_kᵀ.
        const double mean = 0.5 * (s00 + s11), half = 0.5 * (s00 - s11);
        const double radius = std::sqrt(half * half + s01 * s01);
        const double hi = mean + radius, lo = mean - radius;
        if (hi <= 0.0) {
          s00 = s01 = s11 = 0.0;
        } else if (lo < 0.0) {
          // S₊ = hi · v vᵀ, v the eigenvector of hi: S − lo·I = (hi − lo) v vᵀ.
          const double k = hi / (hi - lo);
          s00 = k * (s00 - lo);
          s01 = k * s01;
          s11 = k * (s11 - lo);
        }
      }
      He.topLeftCorner<3, 3>().diagonal().array() += s00;
      He.bottomRightCorner<3, 3>().diagonal().array() += s11;
      He.topRightCorner<3, 3>().diagonal().array() += s01;
      He.bottomLeftCorner<3, 3>().diagonal().array() += s01;
      He *= area;
      // e0 = x1 − x0, e1 = x2 − x0: H_x = Lᵀ H_e L.
      H.block<6, 6>(3, 3) = He;
      for (int j = 0; j < 2; ++j) {
        const Eigen::Matrix3d s = -(He.block<3, 3>(0, 3 * j) + He.block<3, 3>(3, 3 * j));
        H.block<3, 3>(0, 3 + 3 * j) = s;
        H.block<3, 3>(3 + 3 * j, 0) = s.transpose();
      }
      H.block<3, 3>(0, 0) = -(H.block<3, 3>(0, 3) + H.block<3, 3>(0, 6));
    }
  return area * W;
}

void MembraneTerm::makeStiffnessDamping(double betaR) {
  if (!(std::isfinite(betaR) && betaR > 0.0)) throw InputError(name_ + ": beta_R must be finite and > 0");
  dampingReference_ = dampingValue_ = betaR;
}

std::vector<std::string> MembraneTerm::parameterNames() const {
  if (dampingReference_ > 0.0) return {"beta_R"};
  return {"lambda", "mu"};
}

std::vector<double> MembraneTerm::parameterValues() const {
  if (dampingReference_ > 0.0) return {dampingValue_};
  return {lambda_, mu_};
}

void MembraneTerm::setParameterValues(const std::vector<double>& values) {
  validateParameterValues(name_, parameterNames(), values);
  if (dampingReference_ > 0.0) {
    dampingValue_ = values[0];
  } else {
    lambda_ = values[0];
    mu_ = values[1];
  }
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
      return constant<T>(scale_ * ref_.area[f] / dampingReference_) * p[0] * membraneDensity(a, A, P, lambda_, mu_);
    return constant<T>(scale_ * ref_.area[f]) * membraneDensity(a, A, P, p[0], p[1]);
  };
  const std::vector<double> p = parameterValues();
  resetParameterDerivatives(out, x.size(), static_cast<int>(p.size()));
  if (dampingReference_ > 0.0) {
    addParameterDerivatives<3, 1>(table_, x, p.data(), energy, out);
  } else {
    addParameterDerivatives<3, 2>(table_, x, p.data(), energy, out);
  }
}

EnergyTermPtr makeMembraneTerm(const TriMesh& mesh, const ShellReference& reference, double lambda, double mu) {
  return std::make_shared<MembraneTerm>(mesh, reference, lambda, mu);
}

}  // namespace jetshell
