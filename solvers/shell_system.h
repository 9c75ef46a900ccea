// From a shell problem (mesh, material, boundary conditions, loads) to the objective a solver minimizes,
// holding only the terms the analysis needs:
//   membrane            when λ or μ ≠ 0
//   bending             when α or β ≠ 0 (clamped boundary edges as asked)
//   gravity             when hasGravity, g ≠ 0 and ρ_A0 > 0
//   nodal_forces        when some applied nodal force ≠ 0 (scaled by the load factor λ)
//   end_moment, …       statics, one per applied end moment (scaled by λ; energies/end_moment_term.h)
//   inertia             dynamics and dynamic relaxation, when ρ_A0 > 0
//   mass_damping        dynamics when α_R > 0; dynamic relaxation always (its α comes from the relaxation)
//   membrane_damping,   dynamics when β_R > 0 (and the matching elastic term is active)
//   bending_damping
//   contact terms       when the problem has volume colliders or interacting point clouds (solvers/shell_contact.h)
// Statics has no inertia and no dissipation. objective().activeTermNames() is the run summary's list.
// Several actors (ShellProblem::actors): each has its own material, gravity flag, clamps and contact settings,
// and its own mesh over its own vertices, a block of the stacked ones. When their materials agree the elastic
// terms span the whole stacked mesh as for one actor; otherwise each actor gets "membrane/<name>" and
// "bending/<name>" on its own mesh, placed in the objective by a VertexBlockTerm (core/vertex_block_term.h;
// membrane/bending point to the first actor's, which take that actor's vertex ids). Per-actor data (meshes,
// masses, contact samples) grows with the actor, so many actors cost the sum of their sizes.
// Mass damping weights each vertex by its actor's α_R (material().massDampingCoefficient is the largest);
// stiffness damping needs one β_R for all actors.
// The objective is finalized at its first evaluation, so more terms (contact, user energies written as
// ElementEnergyTerm functors) can be added with objective().addTerm() until then.
#pragma once

#include "core/mesh.h"
#include "energies/shell/reference_state.h"
#include "core/topology.h"
#include "energies/end_moment_load.h"
#include "energies/end_moment_term.h"
#include "energies/shell/bending_term.h"
#include "energies/kinetic_terms.h"
#include "energies/shell/material.h"
#include "energies/shell/membrane_term.h"
#include "energies/shell/shell_terms.h"
#include "solvers/objective.h"
#include "solvers/prescribed_positions.h"
#include "solvers/shell_contact.h"

#include <Eigen/Core>

#include <memory>
#include <vector>

namespace jetshell {

/// One shell actor of a multi-actor problem.
struct ShellActorPart {
  std::string name;
  /// The actor's own vertices and its faces over them (ids from 0): the stacked mesh's rows firstVertex … and its
  /// next faces, shifted by firstVertex. Its terms are built on this mesh, so an actor costs its own size.
  TriMesh mesh;
  int firstVertex = 0;  // its vertex 0 in the stacked mesh; the actors' blocks follow one another
  ShellMaterialParams material;
  bool hasGravity = true;
  std::vector<char> clampedVertices;  // the actor's vertex count, or empty
  ContactParams contact;
  ContactQuadrature contactQuadrature = ContactQuadrature::Vertices;
  bool pointCloud = true;  // has a point-cloud collider (shell–shell contact)
  PointCloudColliderParams pointCloudCollider;
};

struct ShellProblem {
  TriMesh mesh;                      // the reference configuration
  ShellMaterialParams material;
  bool hasGravity = true;
  Eigen::Vector3d gravity{0.0, -9.81, 0.0};  // m/s²; y is up, as in the engine the spec comes from
  PrescribedPositions prescribed;    // eliminated dofs
  Eigen::VectorXd nodalForces;       // 3N [N] at load factor 1, or empty
  std::vector<char> clampedVertices;  // N or empty: boundary edges with both ends marked are clamped
  /// Several actors over the stacked `mesh` (its faces = the union of theirs); empty: one actor made of
  /// mesh, material, hasGravity and clampedVertices (with default contact settings).
  std::vector<ShellActorPart> actors;
  /// Rigid volume actors shells collide with.
  std::vector<VolumeColliderPart> volumes;
  /// Applied end moments (AnalysisKind::Statics only; InputError otherwise).
  std::vector<EndMomentLoad> endMoments;
};

/// The block [first, first + count) of a per-vertex mask, or empty when the mask is empty or the block holds no 1
/// (InputError when the block is not inside the mask).
std::vector<char> vertexBlock(const std::vector<char>& mask, int first, int count);

/// The vertices of the problem's end-moment edges (size N), or empty when it has none: the edges whose bending
/// rule must let the applied moment in (energies/shell/boundary_rules.h).
std::vector<char> momentLoadedVertices(const ShellProblem& problem);

enum class AnalysisKind { Statics, Dynamics, DynamicRelaxation };
const char* toString(AnalysisKind k);
/// What runs a volume actor's path in each kind (RigidPath::readBy says which motions each follows): dynamics
/// time, a static path its load factor, a relaxation nothing.
PathClock pathClock(AnalysisKind k);

/// The built system. Not copyable or movable: solvers keep references to its objective.
class ShellSystem {
 public:
  /// Validates the problem (mesh topology, material, sizes; InputError naming the field) and builds the
  /// active terms for `kind`.
  ShellSystem(const ShellProblem& problem, AnalysisKind kind);
  ShellSystem(const ShellSystem&) = delete;
  ShellSystem& operator=(const ShellSystem&) = delete;

  AnalysisKind kind() const { return kind_; }
  const TriMesh& mesh() const { return mesh_; }
  const Topology& topology() const { return topology_; }
  const ShellReference& reference() const { return reference_; }
  const ShellMaterialParams& material() const { return material_; }
  /// The reference positions as a flat 3N vector.
  Eigen::VectorXd restPositions() const { return flatten(mesh_.V); }
  /// Lumped vertex masses m_v (size N).
  const Eigen::VectorXd& vertexMass() const { return vertexMass_; }
  /// Per vertex (size N), its actor's membrane wave speed over the actor's mean reference edge length [1/s]:
  /// c/ℓ with c = √((λ + 2μ)/ρ_A), the speed of a plane-stress compression wave (√(E/(ρ0(1 − ν²)))). A time step
  /// Δt lets the wave cross Δt·c/ℓ edges (the membrane's Courant number); +∞ for a massless actor.
  const Eigen::VectorXd& membraneWaveRate() const { return membraneWaveRate_; }
  /// Per vertex (size N), its actor's mean reference edge length over the thickness its material implies,
  /// h = √(12 (α + β)/(λ + 2μ)) (the 3D thickness for ShellMaterialParamsFrom3dIsotropic): how thin the sheet is
  /// at the mesh's scale (its membrane is 12 (ℓ/h)² times stiffer than its bending there).
  const Eigen::VectorXd& edgeOverThickness() const { return edgeOverThickness_; }

  Objective& objective() { return objective_; }
  const Objective& objective() const { return objective_; }

  // The terms a driver adjusts (null when inactive).
  std::shared_ptr<MembraneTerm> membrane;
  std::shared_ptr<BendingTerm> bending;
  std::shared_ptr<NodalForceTerm> nodalForces;
  std::shared_ptr<GravityTerm> gravity;
  /// One per ShellProblem::endMoments entry, named "end_moment", "end_moment/1", … (solvers/statics.h's
  /// loadFactorHooks scales them with λ and advances their unwrapping after each equilibrium).
  std::vector<std::shared_ptr<EndMomentTerm>> endMoments;
  std::shared_ptr<DiagonalQuadraticTerm> inertia;
  std::shared_ptr<DiagonalQuadraticTerm> massDamping;
  StiffnessDampingTerms stiffnessDamping;
  /// Every bending term: the elastic ones (one per actor when their materials differ; `bending` is the first)
  /// and the stiffness damping's. Boundary-edge rules go to all of them (energies/shell/boundary_rules.h).
  std::vector<std::shared_ptr<BendingTerm>> bendingTerms;
  /// Where bendingTerms[k] sits: the mesh it is built on and the stacked id of that mesh's vertex 0. The stacked
  /// mesh and 0 for a term over every actor (materials that agree, stiffness damping); an actor's own mesh and
  /// first vertex for an actor's term (its masks are the block of the stacked ones: vertexBlock).
  struct TermBlock {
    const TriMesh* mesh;
    int firstVertex;
  };
  std::vector<TermBlock> bendingBlocks;
  /// Every membrane term: the elastic ones and the stiffness damping's (`membrane` is the first).
  std::vector<std::shared_ptr<MembraneTerm>> membraneTerms;
  ShellContact contact;  // empty without colliders

 private:
  AnalysisKind kind_;
  TriMesh mesh_;
  std::vector<TriMesh> actorMeshes_;  // each actor's own mesh (ShellActorPart::mesh)
  Topology topology_;
  ShellReference reference_;
  ShellMaterialParams material_;
  Eigen::VectorXd vertexMass_;
  Eigen::VectorXd membraneWaveRate_, edgeOverThickness_;
  Objective objective_;
};

}  // namespace jetshell
