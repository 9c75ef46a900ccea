// Lumped mass, gravity and external nodal forces: terms linear in x (zero Hessian).
#include "energies/shell/shell_terms.h"

#include "core/parameter_derivatives.h"

#include <cmath>

namespace jetshell {
namespace {

/// −s Σ_v w_v·x_v for one vertex, with s a parameter (any scalar type): the templated energy whose duals give
/// the parameter derivatives of the linear loads.
template <typename T>
T linearLoad(const T* x, const T& s, const double* w) {
  return -s * (w[0] * x[0] + w[1] * x[1] + w[2] * x[2]);
}

}  // namespace

Eigen::VectorXd lumpedMass(const TriMesh& mesh, const ShellReference& reference, double density) {
  Eigen::VectorXd m = Eigen::VectorXd::Zero(mesh.numVertices());
  for (int f = 0; f < mesh.numFaces(); ++f)
    for (int k = 0; k < 3; ++k) m[mesh.F(f, k)] += density * reference.area[f] / 3.0;
  return m;
}

GravityTerm::GravityTerm(const Eigen::VectorXd& mass, const Eigen::Vector3d& g, double density)
    : weight_(mass.size() * 3), referenceDensity_(density), density_(density) {
  if (!(std::isfinite(density) && density > 0.0)) throw InputError("gravity: density must be finite and > 0");
  for (Eigen::Index v = 0; v < mass.size(); ++v) weight_.segment<3>(3 * v) = mass[v] * g;
}

double GravityTerm::evaluate(const Eigen::VectorXd& x, const EvalRequest& request, const EvalOptions&) {
  const double s = loadFactor_ * density_ / referenceDensity_;
  if (request.gradient) *request.gradient -= s * weight_;
  return -s * weight_.dot(x);
}

void GravityTerm::setParameterValues(const std::vector<double>& values) {
  validateParameterValues(name(), parameterNames(), values);
  density_ = values[0];
}

void GravityTerm::evaluateParameterDerivatives(const Eigen::VectorXd& x, ParameterDerivatives& out) {
  resetParameterDerivatives(out, x.size(), 1);
  const double inv = loadFactor_ / referenceDensity_;
  addParameterDerivatives<1, 1>(vertexStencils(static_cast<int>(x.size() / 3)), x, &density_,
                                [&](const auto* xv, const auto* p, int v) {
                                  return linearLoad(xv, inv * p[0], weight_.data() + 3 * v);
                                },
                                out);
}

void GravityTerm::setLoadFactor(double lambda) {
  // Any finite λ: arc-length control may take λ below 0 on the way (a path that turns back past a limit point, or
  // a corrector's iterate), where the weight is reversed, as nodal forces are.
  if (!std::isfinite(lambda)) throw InputError("gravity: load factor must be finite");
  loadFactor_ = lambda;
}

std::shared_ptr<GravityTerm> makeGravityTerm(const Eigen::VectorXd& vertexMass, const Eigen::Vector3d& gravity,
                                             double density) {
  return std::make_shared<GravityTerm>(vertexMass, gravity, density);
}

Eigen::VectorXd NodalForceTerm::forces() const {
  Eigen::VectorXd f = forces_;
  for (std::size_t k = 0; k < parts_.size(); ++k) f += partScales_[k] * parts_[k];
  return f;
}

double NodalForceTerm::evaluate(const Eigen::VectorXd& x, const EvalRequest& request, const EvalOptions&) {
  const double s = scale_ * magnitude_;
  if (parts_.empty()) {
    if (request.gradient) *request.gradient -= s * forces_;
    return -s * forces_.dot(x);
  }
  const Eigen::VectorXd f = forces();
  if (request.gradient) *request.gradient -= s * f;
  return -s * f.dot(x);
}

std::vector<std::string> NodalForceTerm::parameterNames() const {
  std::vector<std::string> names = {"load_factor", "scale"};
  for (const std::string& n : partNames_) names.push_back("scale/" + n);
  return names;
}

std::vector<double> NodalForceTerm::parameterValues() const {
  std::vector<double> values = {scale_, magnitude_};
  values.insert(values.end(), partScales_.begin(), partScales_.end());
  return values;
}

void NodalForceTerm::setParameterValues(const std::vector<double>& values) {
  validateParameterValues(name(), parameterNames(), values);
  scale_ = values[0];
  magnitude_ = values[1];
  for (std::size_t k = 0; k < partScales_.size(); ++k) partScales_[k] = values[2 + k];
}

void NodalForceTerm::evaluateParameterDerivatives(const Eigen::VectorXd& x, ParameterDerivatives& out) {
  // E = −λ s F·x with F = f + Σ s_k f_k: linear in every parameter, so the derivatives are these products.
  const int P = 2 + static_cast<int>(parts_.size());
  resetParameterDerivatives(out, x.size(), P);
  const Eigen::VectorXd F = forces();
  out.energy[0] = -magnitude_ * F.dot(x);
  out.energy[1] = -scale_ * F.dot(x);
  out.mixed.col(0) = -magnitude_ * F;
  out.mixed.col(1) = -scale_ * F;
  for (std::size_t k = 0; k < parts_.size(); ++k) {
    const Eigen::Index c = static_cast<Eigen::Index>(2 + k);
    out.energy[c] = -scale_ * magnitude_ * parts_[k].dot(x);
    out.mixed.col(c) = -scale_ * magnitude_ * parts_[k];
  }
}

void NodalForceTerm::addNamedPart(const std::string& name, const Eigen::VectorXd& part) {
  if (part.size() != forces_.size()) throw InputError("nodal_forces: the part '" + name + "' has the wrong size");
  if (!part.allFinite()) throw InputError("nodal_forces: the part '" + name + "' is not finite");
  for (const std::string& n : partNames_)
    if (n == name) throw InputError("nodal_forces: the part '" + name + "' is split off twice");
  forces_ -= part;
  partNames_.push_back(name);
  parts_.push_back(part);
  partScales_.push_back(1.0);
}

StiffnessDampingTerms makeStiffnessDampingTerms(const TriMesh& mesh, const Topology& topology,
                                                const ShellReference& reference, const ShellMaterialParams& m) {
  StiffnessDampingTerms t;
  if (m.stiffnessDampingCoefficient <= 0.0) return t;
  if (m.membraneLambda != 0.0 || m.membraneMu != 0.0) {
    t.membrane = std::make_shared<MembraneTerm>(mesh, reference, m.membraneLambda, m.membraneMu);
    t.membrane->setName("membrane_damping");
    t.membrane->makeStiffnessDamping(m.stiffnessDampingCoefficient);
  }
  if (m.bendingAlpha != 0.0 || m.bendingBeta != 0.0) {
    t.bending = std::make_shared<BendingTerm>(mesh, topology, reference, m.bendingAlpha, m.bendingBeta);
    t.bending->setName("bending_damping");
    t.bending->makeStiffnessDamping(m.stiffnessDampingCoefficient);
  }
  return t;
}

std::shared_ptr<NodalForceTerm> makeNodalForceTerm(const Eigen::VectorXd& forces) {
  return std::make_shared<NodalForceTerm>(forces);
}

}  // namespace jetshell
