// Lumped mass, gravity and external nodal forces: terms linear in x (zero Hessian).
#include "energies/shell_terms.h"

namespace jetshell {
namespace {

class GravityTerm : public EnergyTerm {
 public:
  GravityTerm(const Eigen::VectorXd& mass, const Eigen::Vector3d& g) : weight_(mass.size() * 3) {
    for (Eigen::Index v = 0; v < mass.size(); ++v) weight_.segment<3>(3 * v) = mass[v] * g;
  }
  std::string name() const override { return "gravity"; }
  StencilTable stencils() const override { return {}; }
  bool hasAnalytic() const override { return true; }
  bool zeroAtRest() const override { return false; }
  bool rigidInvariant() const override { return false; }
  double evaluate(const Eigen::VectorXd& x, const EvalRequest& request, const EvalOptions&) override {
    if (request.gradient) *request.gradient -= weight_;
    return -weight_.dot(x);
  }

 private:
  Eigen::VectorXd weight_;  // m_v g per dof
};

}  // namespace

Eigen::VectorXd lumpedMass(const TriMesh& mesh, const ShellReference& reference, double density) {
  Eigen::VectorXd m = Eigen::VectorXd::Zero(mesh.numVertices());
  for (int f = 0; f < mesh.numFaces(); ++f)
    for (int k = 0; k < 3; ++k) m[mesh.F(f, k)] += density * reference.area[f] / 3.0;
  return m;
}

EnergyTermPtr makeGravityTerm(const Eigen::VectorXd& vertexMass, const Eigen::Vector3d& gravity) {
  return std::make_shared<GravityTerm>(vertexMass, gravity);
}

double NodalForceTerm::evaluate(const Eigen::VectorXd& x, const EvalRequest& request, const EvalOptions&) {
  if (request.gradient) *request.gradient -= scale_ * forces_;
  return -scale_ * forces_.dot(x);
}

std::shared_ptr<NodalForceTerm> makeNodalForceTerm(const Eigen::VectorXd& forces) {
  return std::make_shared<NodalForceTerm>(forces);
}

}  // namespace jetshell
