// Contact between a shell and a rigid volume actor: three energy terms over the shell's contact samples
// (energies/contact/contact_sampling.h), each written once for any scalar type and differentiated by the
// framework (ElementEnergyTerm):
//   contact_penalty   Σ_q A_q k R(p_q)                    (Potential)
//   contact_damping   Σ_q A_q (c k / Δt) [G(p_q) − a_q R(p_q)]   (Transient: Hunt–Crossley)
//   contact_friction  Σ_q μ λ_q f₀(‖P_q u_q‖)             (Transient: regularized Coulomb dissipation)
// with p_q = ε − d(x_q, t) the penetration of sample point x_q into the activation band of the collider at the
// end-of-step time t, R, G the C²-smoothed ramp and its moment (energies/contact/contact_ramp.h), and lagged
// at the start of the step (beginStep): a_q = p(x_q^n, t_n), λ_q = A_q k r(a_q) (the normal force),
// P_q = I − n nᵀ (n = ∇d there), u_q = x_q − x_q^n − m_q (the slip relative to the solid, m_q the move over the
// step of the solid's material at x_q^n: VolumeCollider::materialMove),
// f₀ with ε_v = V_f Δt. ∂/∂p of the damping potential is A_q k r(p) · c (p − a_q)/Δt: the Hunt–Crossley force
// k r(p) c ṗ. Both transient terms are zero until a step begins (statics).
// Damping and friction energies, differentiated, are forces of the step, not potential energies of the state.
#pragma once

#include "core/mesh.h"
#include "energies/contact/contact_params.h"
#include "energies/contact/contact_sampling.h"
#include "energies/contact/volume_collider.h"
#include "core/term.h"

#include <memory>
#include <string>
#include <vector>

namespace jetshell {

/// What the three terms of one (shell, collider) pair share; beginStep updates the lagged data.
struct VolumeContactState {
  VolumeContactState(ContactSampling sampling, VolumeColliderPtr collider, const ContactParams& params);

  ContactSampling sampling;  // over the shell's own vertex ids (0 … its count − 1)
  VolumeColliderPtr collider;
  ContactParams params;
  int firstVertex = 0;  // the problem's id of the shell's vertex 0: point(x) reads x (3N) there
  double time = 0.0;      // t at which the collider is evaluated (end of the step)
  double timeStep = 0.0;  // Δt of the current step; 0 before the first step
  // Lagged per sample point (element × Q + q), from beginStep.
  std::vector<double> previousPenetration;  // a_q [m]
  std::vector<double> normalForce;          // λ_q [N]
  std::vector<Eigen::Vector3d> normal, start, colliderShift;

  /// Sample point positions of element e from x (3N).
  Eigen::Vector3d point(const Eigen::VectorXd& x, int e, int q) const;
  /// Lags the step-start data from x_n (3N) at t_n; the step ends at t_n + h.
  void beginStep(const Eigen::VectorXd& xStart, double tStart, double h);
  /// Largest α ≤ 1 such that no sample point approaches the surface by more than `fraction` of its distance
  /// to it, of the activation distance, or of the solid's thinnest half-width, whichever is largest, along
  /// x + α d: so no sample passes through the solid in one step (1 for the half-space).
  double stepBound(const Eigen::VectorXd& x, const Eigen::VectorXd& d, double fraction) const;
  /// Min over sample points of the signed distance (m): how deep the shell is in the collider.
  double minDistance(const Eigen::VectorXd& x) const;
  /// The force the shell's contact penalty exerts on the solid at x (3N), the solid where it is at time t [N]: the
  /// sum over the sample points of −A_q k r(p_q) ∇d, the reaction to the penalty's push on the shell (friction
  /// and damping, forces of a step, are not counted).
  Eigen::Vector3d forceOnSolid(const Eigen::VectorXd& x, double t) const;
  /// The longest path the solid's material travels over [tStart, tStart + h] (a path, not a chord: a whole turn
  /// counts its circumference) at a sample point it may reach in that time: one whose distance at tStart is at
  /// most that move, the sample's own move (|velocity| h) and the activation distance [m]. 0 for a static solid;
  /// a turn that leaves its surface in place (a ball about its centre, a capsule about its axis:
  /// VolumeShape::surfaceTurning) moves nothing; across keyframes the moves over each piece of the step add up
  /// (RigidPath::piecesOver). x, v: positions and velocities (3N) at tStart.
  double solidTravel(const Eigen::VectorXd& x, const Eigen::VectorXd& v, double tStart, double h) const;
};

struct VolumeContactTerms {
  std::shared_ptr<VolumeContactState> state;
  EnergyTermPtr penalty;   // Potential
  EnergyTermPtr damping;   // Transient; null when c = 0
  EnergyTermPtr friction;  // Transient; null when μ = 0
};

/// Builds the terms for one shell and one collider: the sampling is over the shell's numVertices vertices, which
/// are the problem's vertices firstVertex … (the terms sit there through a VertexBlockTerm when firstVertex > 0,
/// core/vertex_block_term.h). Names are "contact_penalty<suffix>", "contact_damping<suffix>",
/// "contact_friction<suffix>".
VolumeContactTerms makeVolumeContactTerms(ContactSampling sampling, int numVertices, VolumeColliderPtr collider,
                                          const ContactParams& params, const std::string& suffix = "",
                                          int firstVertex = 0);

}  // namespace jetshell
