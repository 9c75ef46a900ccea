// Factories for the built-in shell energy terms. Each returns an EnergyTerm over 3N position dofs.
#pragma once

#include "core/mesh.h"
#include "energies/shell/reference_state.h"
#include "core/term.h"
#include "core/topology.h"
#include "energies/shell/bending_term.h"
#include "energies/shell/material.h"
#include "energies/shell/membrane_term.h"

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

/// Stiffness damping (β_R) for an implicit step: "membrane_damping" and "bending_damping", the membrane and
/// bending energies with their origin moved to x_prev and scaled by β_R/Δt, which makes
/// Δt·β_R·(W_m(ε̇) + W_b(κ̇)) with ε̇ = (ε(x) − ε(x_prev))/Δt, κ̇ likewise, a potential. Before each step call
/// membrane->setStrainOrigin(x_prev, β_R/Δt) and bending->setCurvatureOrigin(x_prev, β_R/Δt).
/// Either pointer is null when its coefficients are zero (the term is not needed).
struct StiffnessDampingTerms {
  std::shared_ptr<MembraneTerm> membrane;
  std::shared_ptr<BendingTerm> bending;
};
StiffnessDampingTerms makeStiffnessDampingTerms(const TriMesh& mesh, const Topology& topology,
                                                const ShellReference& reference, const ShellMaterialParams& material);

/// Lumped mass per vertex: each face gives a third of ρ_A0 · area to each of its vertices.
Eigen::VectorXd lumpedMass(const TriMesh& mesh, const ShellReference& reference, double density);

/// Gravity: −λ (ρ/ρ₀) Σ_v m_v g·x_v with the per-vertex masses m_v given at the density ρ₀ = `density` (> 0).
/// Its parameter "density" is ρ (initially ρ₀): a mass scale per unit density, so that ∂E/∂ρ is the
/// sensitivity to the material density when the masses come from lumpedMass(mesh, reference, ρ₀). λ is the
/// load factor (1 unless set): load stepping ramps the weight with the other loads (solvers/statics.h,
/// LoadFactorHooks); dynamics keeps it at 1 (a body force, not a load to ramp).
class GravityTerm;
std::shared_ptr<GravityTerm> makeGravityTerm(const Eigen::VectorXd& vertexMass, const Eigen::Vector3d& gravity,
                                             double density = 1.0);

class GravityTerm : public EnergyTerm {
 public:
  GravityTerm(const Eigen::VectorXd& vertexMass, const Eigen::Vector3d& gravity, double density);
  std::string name() const override { return "gravity"; }
  StencilTable stencils() const override { return {}; }
  bool hasAnalytic() const override { return true; }
  bool zeroAtRest() const override { return false; }
  bool rigidInvariant() const override { return false; }
  double evaluate(const Eigen::VectorXd& x, const EvalRequest& request, const EvalOptions& options) override;
  std::vector<std::string> parameterNames() const override { return {"density"}; }
  std::vector<double> parameterValues() const override { return {density_}; }
  void setParameterValues(const std::vector<double>& values) override;
  void evaluateParameterDerivatives(const Eigen::VectorXd& x, ParameterDerivatives& out) override;
  /// λ: finite (InputError otherwise); below 0 the weight is reversed (arc-length control may go there).
  void setLoadFactor(double lambda);
  double loadFactor() const { return loadFactor_; }

 private:
  Eigen::VectorXd weight_;  // m_v g per dof, at the reference density
  double referenceDensity_, density_;
  double loadFactor_ = 1.0;  // λ
};

/// External nodal forces: −λ·s·(f + Σ_k s_k f_k)·x. forces has size 3N; λ is the load factor (the parameter
/// "load_factor", which load stepping and time ramps drive), s a magnitude scale (the parameter "scale", 1 unless a
/// fit changes it), and s_k the scale of a named part f_k of the loads (parameters "scale/<name>", 1 until changed;
/// see addNamedPart). The energy is linear in each parameter: its parameter derivatives are exact formulas.
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
  std::vector<std::string> parameterNames() const override;
  std::vector<double> parameterValues() const override;
  void setParameterValues(const std::vector<double>& values) override;
  void evaluateParameterDerivatives(const Eigen::VectorXd& x, ParameterDerivatives& out) override;
  double loadFactor() const { return scale_; }
  /// f + Σ s_k f_k (at load factor 1 and scale 1).
  Eigen::VectorXd forces() const;
  /// Splits the named part `part` (3N, a load of the scene's) off the forces: its scale s_k becomes the
  /// parameter "scale/<name>". The total is unchanged while s_k = 1. Throws InputError for a repeated name or a
  /// part of the wrong size.
  void addNamedPart(const std::string& name, const Eigen::VectorXd& part);

 private:
  Eigen::VectorXd forces_;  // f: the loads not split off
  double scale_ = 1.0;      // λ
  double magnitude_ = 1.0;  // s
  std::vector<std::string> partNames_;
  std::vector<Eigen::VectorXd> parts_;  // f_k
  std::vector<double> partScales_;      // s_k
};

}  // namespace jetshell
