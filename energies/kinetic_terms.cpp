#include "energies/kinetic_terms.h"

#include "core/mesh.h"
#include "core/parameter_derivatives.h"

#include <cmath>
#include <sstream>

namespace jetshell {

DiagonalQuadraticTerm::DiagonalQuadraticTerm(std::string name, Eigen::VectorXd vertexMass, std::string parameter,
                                             double parameterValue)
    : name_(std::move(name)),
      mass_(std::move(vertexMass)),
      centre_(Eigen::VectorXd::Zero(3 * mass_.size())),
      parameter_(std::move(parameter)),
      parameterReference_(parameterValue),
      parameterValue_(parameterValue) {
  if (!(std::isfinite(parameterValue) && parameterValue > 0.0))
    throw InputError(name_ + ": " + parameter_ + " must be finite and > 0");
  for (Eigen::Index v = 0; v < mass_.size(); ++v) {
    if (!(std::isfinite(mass_[v]) && mass_[v] >= 0.0)) {
      std::ostringstream s;
      s << name_ << ": vertexMass[" << v << "] = " << mass_[v] << ": must be finite and >= 0";
      throw InputError(s.str());
    }
  }
  table_ = vertexStencils(static_cast<int>(mass_.size()));
}

void DiagonalQuadraticTerm::setParameterValues(const std::vector<double>& values) {
  validateParameterValues(name_, parameterNames(), values);
  parameterValue_ = values[0];
}

void DiagonalQuadraticTerm::evaluateParameterDerivatives(const Eigen::VectorXd& x, ParameterDerivatives& out) {
  resetParameterDerivatives(out, x.size(), 1);
  // ½ c (q/q₀) m_v |x_v − y_v|² per vertex, with q a dual.
  const double k = 0.5 * coefficient_ / parameterReference_;
  addParameterDerivatives<1, 1>(table_, x, &parameterValue_,
                                [&](const auto* xv, const auto* q, int v) {
                                  using T = std::remove_const_t<std::remove_pointer_t<decltype(xv)>>;
                                  const V3<T> y{{constant<T>(centre_[3 * v]), constant<T>(centre_[3 * v + 1]),
                                                 constant<T>(centre_[3 * v + 2])}};
                                  return (k * mass_[v]) * q[0] * squaredNorm(load3(xv) - y);
                                },
                                out);
}

Eigen::MatrixXd DiagonalQuadraticTerm::centreCrossDerivatives(const Eigen::MatrixXd& S) const {
  if (S.rows() != centre_.size()) throw InputError(name_ + ": centre directions have the wrong size");
  Eigen::MatrixXd out(S.rows(), S.cols());
  const double c = effectiveCoefficient();
  for (Eigen::Index v = 0; v < mass_.size(); ++v) out.middleRows<3>(3 * v) = (-c * mass_[v]) * S.middleRows<3>(3 * v);
  return out;
}

void DiagonalQuadraticTerm::setCentre(const Eigen::VectorXd& centre, double coefficient) {
  if (centre.size() != centre_.size()) throw InputError(name_ + ": centre has the wrong size");
  if (!(std::isfinite(coefficient) && coefficient >= 0.0))
    throw InputError(name_ + ": coefficient must be finite and >= 0");
  centre_ = centre;
  coefficient_ = coefficient;
}

double DiagonalQuadraticTerm::evaluate(const Eigen::VectorXd& x, const EvalRequest& request, const EvalOptions&) {
  const Eigen::Index n = mass_.size();
  double energy = 0.0;
  // Vertices share nothing, so the loop is trivially parallel; the serial energy sum keeps the bits fixed.
  for (Eigen::Index v = 0; v < n; ++v) {
    const Eigen::Vector3d d = x.segment<3>(3 * v) - centre_.segment<3>(3 * v);
    energy += mass_[v] * d.squaredNorm();
  }
  const double c = effectiveCoefficient();
  energy *= 0.5 * c;
  if (request.gradient != nullptr) {
    Eigen::VectorXd& g = *request.gradient;
#pragma omp parallel for schedule(static)
    for (Eigen::Index v = 0; v < n; ++v)
      g.segment<3>(3 * v) += c * mass_[v] * (x.segment<3>(3 * v) - centre_.segment<3>(3 * v));
  }
  if (request.hessian != nullptr) {
    HessianAssembler& A = *request.hessian;
    const int slot = request.hessianSlot;
#pragma omp parallel for schedule(static)
    for (Eigen::Index v = 0; v < n; ++v) {
      const double k = c * mass_[v];
      const double H[9] = {k, 0.0, 0.0, 0.0, k, 0.0, 0.0, 0.0, k};
      A.addElementHessian(slot, static_cast<int>(v), H);
    }
  }
  return energy;
}

std::shared_ptr<DiagonalQuadraticTerm> makeInertiaTerm(const Eigen::VectorXd& vertexMass, double density) {
  return std::make_shared<DiagonalQuadraticTerm>("inertia", vertexMass, "density", density);
}

std::shared_ptr<DiagonalQuadraticTerm> makeMassDampingTerm(const Eigen::VectorXd& vertexMass, double alphaR) {
  return std::make_shared<DiagonalQuadraticTerm>("mass_damping", vertexMass, "alpha_R", alphaR);
}

}  // namespace jetshell
