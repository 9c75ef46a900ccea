// Lumped mass, gravity and external nodal forces: terms linear in x (zero Hessian).
#include "energies/shell/shell_terms.h"

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

StiffnessDampingTerms makeStiffnessDampingTerms(const TriMesh& mesh, const Topology& topology,
                                                const ShellReference& reference, const ShellMaterialParams& m) {
  StiffnessDampingTerms t;
  if (m.stiffnessDampingCoefficient <= 0.0) return t;
  if (m.membraneLambda != 0.0 || m.membraneMu != 0.0) {
    t.membrane = std::make_shared<MembraneTerm>(mesh, reference, m.membraneLambda, m.membraneMu);
    t.membrane->setName("membrane_damping");
  }
  if (m.bendingAlpha != 0.0 || m.bendingBeta != 0.0) {
    t.bending = std::make_shared<BendingTerm>(mesh, topology, reference, m.bendingAlpha, m.bendingBeta);
    t.bending->setName("bending_damping");
  }
  return t;
}

std::shared_ptr<NodalForceTerm> makeNodalForceTerm(const Eigen::VectorXd& forces) {
  return std::make_shared<NodalForceTerm>(forces);
}

}  // namespace jetshell
