// Hand-derived twins of the nonlinear stages in energies/shell/shell_geometry.h. The conformance suite checks each
// against its Jet-derived counterpart (core/stage_derivatives.h) to ~1e-12 relative.
#pragma once

#include <Eigen/Core>

#include <array>

namespace jetshell::analytic {

/// [v]×, the matrix of v × (·): [v]× u = v × u. The cross product c = e0 × e1 has ∂c/∂e0 = −[e1]×, ∂c/∂e1 = [e0]×.
inline Eigen::Matrix3d crossMatrix(const Eigen::Vector3d& v) {
  Eigen::Matrix3d s;
  s << 0.0, -v[2], v[1], v[2], 0.0, -v[0], -v[1], v[0], 0.0;
  return s;
}

/// Value, gradient and Hessian of the St. Venant–Kirchhoff quadratic in a symmetric 2×2 tensor d stored as
/// (d00, d01, d11):  W = c1/2 (tr_P d)² + c2 tr(P d P d), traces with the symmetric P = A⁻¹.
/// Membrane: d = a − A, c1 = λ/4, c2 = μ/4. Bending: d = b − B, c1 = α, c2 = β/2.
void stvkQuadratic(const double P[3], double c1, double c2, const double d[3], double& value,
                   Eigen::Vector3d& gradient, Eigen::Matrix3d& hessian);

/// The same W and ∇W without the Hessian (what a value-and-gradient request needs), to the bit those of the
/// overload above: ∇W = c1 (tr_P d) t + 2 c2 G d, with G d formed from the four entries of P d, not from G.
void stvkQuadratic(const double P[3], double c1, double c2, const double d[3], double& value,
                   Eigen::Vector3d& gradient);

/// n = c/‖c‖: value, Jacobian, and Hessian of each component.
void unitNormal(const Eigen::Vector3d& c, Eigen::Vector3d& n, Eigen::Matrix3d& jacobian,
                std::array<Eigen::Matrix3d, 3>& hessians);

/// n = c/‖c‖: C = Σ_k w_k ∇²n_k = (3(w·n) n nᵀ − w nᵀ − n wᵀ − (w·n) I)/‖c‖², without the three Hessians.
void unitNormalWeightedHessian(const Eigen::Vector3d& c, const Eigen::Vector3d& w, Eigen::Matrix3d& C);

/// n = c/‖c‖: value and Jacobian only.
void unitNormal(const Eigen::Vector3d& c, Eigen::Vector3d& n, Eigen::Matrix3d& jacobian);

/// n̄ = m/‖m‖²: value and Jacobian only.
void kelvinInversion(const Eigen::Vector3d& m, Eigen::Vector3d& nbar, Eigen::Matrix3d& jacobian);

/// n̄ = m/‖m‖²: C = Σ_k w_k ∇²n̄_k = 8(w·m) m mᵀ/q³ − 2(w mᵀ + m wᵀ + (w·m) I)/q² (q = ‖m‖²), without the three
/// Hessians.
void kelvinInversionWeightedHessian(const Eigen::Vector3d& m, const Eigen::Vector3d& w, Eigen::Matrix3d& C);

/// n̄ = m/‖m‖²: value, Jacobian, and Hessian of each component.
void kelvinInversion(const Eigen::Vector3d& m, Eigen::Vector3d& nbar, Eigen::Matrix3d& jacobian,
                     std::array<Eigen::Matrix3d, 3>& hessians);

}  // namespace jetshell::analytic
