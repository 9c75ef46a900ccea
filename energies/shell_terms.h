// Factories for the built-in shell energy terms. Each returns an EnergyTerm over 3N position dofs.
#pragma once

#include "core/mesh.h"
#include "core/reference_state.h"
#include "core/term.h"
#include "core/topology.h"
#include "energies/material.h"

#include <Eigen/Core>

namespace jetshell {

/// St. Venant–Kirchhoff membrane on constant-strain triangles: Σ_f area_f · W_m(ε_f). AD and analytic paths.
EnergyTermPtr makeMembraneTerm(const TriMesh& mesh, const ShellReference& reference, double lambda, double mu);

/// St. Venant–Kirchhoff bending on the four-triangle stencil with Kelvin-inverted mid-edge normals:
/// Σ_f area_f · W_b(κ_f). Staged AD and analytic paths; exact or Gauss–Newton Hessian (EvalOptions).
EnergyTermPtr makeBendingTerm(const TriMesh& mesh, const Topology& topology, const ShellReference& reference,
                              double alpha, double beta);

/// The same bending energy evaluated naively as one 18-dof element with nested Jets (slow; the reference the
/// staged evaluator is checked against).
EnergyTermPtr makeBendingTermNestedJet(const TriMesh& mesh, const Topology& topology,
                                       const ShellReference& reference, double alpha, double beta);

/// Lumped mass per vertex: each face gives a third of ρ_A0 · area to each of its vertices.
Eigen::VectorXd lumpedMass(const TriMesh& mesh, const ShellReference& reference, double density);

/// Gravity: −Σ_v m_v g·x_v (constant per-vertex masses).
EnergyTermPtr makeGravityTerm(const Eigen::VectorXd& vertexMass, const Eigen::Vector3d& gravity);

/// External nodal forces: −scale·Σ f·x. forces has size 3N; scale is the load factor λ (settable).
class NodalForceTerm;
std::shared_ptr<NodalForceTerm> makeNodalForceTerm(const Eigen::VectorXd& forces);

class NodalForceTerm : public EnergyTerm {
 public:
  explicit NodalForceTerm(Eigen::VectorXd forces) : forces_(std::move(forces)) {}
  std::string name() const override { return "nodal_forces"; }
  StencilTable stencils() const override { return {}; }
  bool hasAnalytic() const override { return true; }
  bool zeroAtRest() const override { return false; }
  bool rigidInvariant() const override { return false; }
  double evaluate(const Eigen::VectorXd& x, const EvalRequest& request, const EvalOptions& options) override;
  void setLoadFactor(double s) { scale_ = s; }
  double loadFactor() const { return scale_; }
  const Eigen::VectorXd& forces() const { return forces_; }

 private:
  Eigen::VectorXd forces_;
  double scale_ = 1.0;
};

}  // namespace jetshell
