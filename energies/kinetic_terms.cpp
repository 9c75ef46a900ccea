#include "energies/kinetic_terms.h"

#include "core/mesh.h"

#include <cmath>
#include <sstream>

namespace jetshell {

DiagonalQuadraticTerm::DiagonalQuadraticTerm(std::string name, Eigen::VectorXd vertexMass)
    : name_(std::move(name)), mass_(std::move(vertexMass)), centre_(Eigen::VectorXd::Zero(3 * mass_.size())) {
  for (Eigen::Index v = 0; v < mass_.size(); ++v) {
    if (!(std::isfinite(mass_[v]) && mass_[v] >= 0.0)) {
      std::ostringstream s;
      s << name_ << ": vertexMass[" << v << "] = " << mass_[v] << ": must be finite and >= 0";
      throw InputError(s.str());
    }
  }
  table_.width = 1;
  table_.ids.resize(static_cast<std::size_t>(mass_.size()));
  for (Eigen::Index v = 0; v < mass_.size(); ++v) table_.ids[static_cast<std::size_t>(v)] = static_cast<int>(v);
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
  energy *= 0.5 * coefficient_;
  if (request.gradient != nullptr) {
    Eigen::VectorXd& g = *request.gradient;
#pragma omp parallel for schedule(static)
    for (Eigen::Index v = 0; v < n; ++v)
      g.segment<3>(3 * v) += coefficient_ * mass_[v] * (x.segment<3>(3 * v) - centre_.segment<3>(3 * v));
  }
  if (request.hessian != nullptr) {
    HessianAssembler& A = *request.hessian;
    const int slot = request.hessianSlot;
#pragma omp parallel for schedule(static)
    for (Eigen::Index v = 0; v < n; ++v) {
      const double k = coefficient_ * mass_[v];
      const double H[9] = {k, 0.0, 0.0, 0.0, k, 0.0, 0.0, 0.0, k};
      A.addElementHessian(slot, static_cast<int>(v), H);
    }
  }
  return energy;
}

std::shared_ptr<DiagonalQuadraticTerm> makeInertiaTerm(const Eigen::VectorXd& vertexMass) {
  return std::make_shared<DiagonalQuadraticTerm>("inertia", vertexMass);
}

std::shared_ptr<DiagonalQuadraticTerm> makeMassDampingTerm(const Eigen::VectorXd& vertexMass) {
  return std::make_shared<DiagonalQuadraticTerm>("mass_damping", vertexMass);
}

}  // namespace jetshell
