#include "energies/shell/analytic_stages.h"

#include <Eigen/Dense>

#include <cmath>

namespace jetshell::analytic {

namespace {

/// W and ∇W, one routine for both overloads (kept out of line, so that a gradient does not change in its last bits
/// with whether a Hessian was asked: a Newton step that skipped its Hessian compares residuals with one that did).
/// tr_P d = t·d with t = (P00, 2P01, P11); tr(PdPd) = dᵀ G d with G = uuᵀ + vwᵀ + wvᵀ + zzᵀ, u, v, w, z such that
/// the rows of P d are (Pd)00 = u·d, (Pd)01 = v·d, (Pd)10 = w·d, (Pd)11 = z·d; G d = u (u·d) + v (w·d) + w (v·d) +
/// z (z·d) and dᵀ G d = (u·d)² + 2 (v·d)(w·d) + (z·d)², formed without G.
[[gnu::noinline]] void stvkValueGradient(const double P[3], double c1, double c2, const double d[3], double& value,
                                         Eigen::Vector3d& gradient) {
  const double pu = P[0] * d[0] + P[1] * d[1], pv = P[0] * d[1] + P[1] * d[2];
  const double pw = P[1] * d[0] + P[2] * d[1], pz = P[1] * d[1] + P[2] * d[2];
  const double tr = P[0] * d[0] + 2.0 * P[1] * d[1] + P[2] * d[2];
  const Eigen::Vector3d Gd(P[0] * pu + P[1] * pv, P[1] * pu + P[0] * pw + P[2] * pv + P[1] * pz, P[1] * pw + P[2] * pz);
  value = 0.5 * c1 * tr * tr + c2 * (pu * pu + 2.0 * pv * pw + pz * pz);
  gradient = (c1 * tr) * Eigen::Vector3d(P[0], 2.0 * P[1], P[2]) + (2.0 * c2) * Gd;
}

}  // namespace

void stvkQuadratic(const double P[3], double c1, double c2, const double d[3], double& value,
                   Eigen::Vector3d& gradient, Eigen::Matrix3d& hessian) {
  stvkValueGradient(P, c1, c2, d, value, gradient);
  const Eigen::Vector3d t(P[0], 2.0 * P[1], P[2]);
  const Eigen::Vector3d u(P[0], P[1], 0.0), v(0.0, P[0], P[1]), w(P[1], P[2], 0.0), z(0.0, P[1], P[2]);
  const Eigen::Matrix3d G = u * u.transpose() + v * w.transpose() + w * v.transpose() + z * z.transpose();
  hessian = c1 * t * t.transpose() + 2.0 * c2 * G;
}

void stvkQuadratic(const double P[3], double c1, double c2, const double d[3], double& value,
                   Eigen::Vector3d& gradient) {
  stvkValueGradient(P, c1, c2, d, value, gradient);
}

void unitNormal(const Eigen::Vector3d& c, Eigen::Vector3d& n, Eigen::Matrix3d& jacobian) {
  const double r = c.norm();
  n = c / r;
  jacobian = (Eigen::Matrix3d::Identity() - n * n.transpose()) / r;
}

void kelvinInversion(const Eigen::Vector3d& m, Eigen::Vector3d& nbar, Eigen::Matrix3d& jacobian) {
  const double q = m.squaredNorm();
  nbar = m / q;
  jacobian = Eigen::Matrix3d::Identity() / q - (2.0 / (q * q)) * m * m.transpose();
}

void unitNormal(const Eigen::Vector3d& c, Eigen::Vector3d& n, Eigen::Matrix3d& jacobian,
                std::array<Eigen::Matrix3d, 3>& hessians) {
  unitNormal(c, n, jacobian);
  const double r = c.norm();
  // ∂²n_k/∂c_j∂c_l = −(δ_kj n_l + δ_kl n_j + δ_jl n_k − 3 n_k n_j n_l)/r².
  const double r2 = r * r;
  for (int k = 0; k < 3; ++k) {
    Eigen::Matrix3d& H = hessians[k];
    H = (3.0 * n[k]) * n * n.transpose() - n[k] * Eigen::Matrix3d::Identity();
    H.row(k) -= n.transpose();
    H.col(k) -= n;
    H /= r2;
  }
}

void kelvinInversion(const Eigen::Vector3d& m, Eigen::Vector3d& nbar, Eigen::Matrix3d& jacobian,
                     std::array<Eigen::Matrix3d, 3>& hessians) {
  kelvinInversion(m, nbar, jacobian);
  const double q = m.squaredNorm();
  // ∂²n̄_k/∂m_j∂m_l = −2(δ_kj m_l + δ_kl m_j + δ_jl m_k)/q² + 8 m_k m_j m_l/q³.
  const double q2 = q * q, q3 = q2 * q;
  for (int k = 0; k < 3; ++k) {
    Eigen::Matrix3d& H = hessians[k];
    H = (8.0 * m[k] / q3) * m * m.transpose() - (2.0 * m[k] / q2) * Eigen::Matrix3d::Identity();
    H.row(k) -= (2.0 / q2) * m.transpose();
    H.col(k) -= (2.0 / q2) * m;
  }
}

void unitNormalWeightedHessian(const Eigen::Vector3d& c, const Eigen::Vector3d& w, Eigen::Matrix3d& C) {
  const double r2 = c.squaredNorm();
  const Eigen::Vector3d n = c / std::sqrt(r2);
  const double wn = w.dot(n);
  const Eigen::Vector3d a = 1.5 * wn * n - w;  // 3(w·n) n nᵀ − w nᵀ − n wᵀ = a nᵀ + n aᵀ
  C = (a * n.transpose() + n * a.transpose()) / r2;
  C.diagonal().array() -= wn / r2;
}

void kelvinInversionWeightedHessian(const Eigen::Vector3d& m, const Eigen::Vector3d& w, Eigen::Matrix3d& C) {
  const double q = m.squaredNorm(), q2 = q * q;
  const double wm = w.dot(m);
  const Eigen::Vector3d a = (2.0 * wm / q) * m - w;  // 8(w·m)/q m mᵀ − 2(w mᵀ + m wᵀ) = 2(a mᵀ + m aᵀ)
  C = (2.0 / q2) * (a * m.transpose() + m * a.transpose());
  C.diagonal().array() -= 2.0 * wm / q2;
}

}  // namespace jetshell::analytic
