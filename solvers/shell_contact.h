// Contact terms of a shell problem: what ShellSystem adds to its objective when the problem has colliders.
//
// Input: the shell actors' contact settings (per actor: faces over the stacked vertices, contact parameters,
// sampling, point-cloud collider) and the rigid volume colliders with their contact parameters.
// Output, added to the objective:
//   per (shell actor, volume collider): contact_penalty/<actor>/<volume> (Potential) and, in dynamics,
//     contact_damping/... (when c > 0) and contact_friction/... (when μ > 0) (Transient); pair coefficients
//     are geometric means;
//   when at least two actors have point-cloud colliders, or one has self-contact: pointcloud_penalty
//     (Potential) and, in dynamics, pointcloud_friction (Transient);
//   the objective's step-start hooks (lagged normal forces, damping origins, friction pairs) and its step
//     bounds: with point clouds, no sample approaches another by more than `stepFraction` of their distance in
//     one Newton step; with a solid of finite thickness (not the half-space), no sample approaches it by more than
//     `stepFraction` of its distance, of the activation distance or of the solid's thinnest half-width, whichever
//     is largest, so nothing passes through a thin solid in one step.
// With no volume collider and no interacting point cloud nothing is built and no detection ever runs.
#pragma once

#include "core/mesh.h"
#include "energies/contact/contact_params.h"
#include "energies/contact/contact_sampling.h"
#include "energies/contact/point_cloud_contact.h"
#include "energies/contact/volume_contact.h"
#include "solvers/objective.h"

#include <string>
#include <utility>
#include <vector>

namespace jetshell {

struct ShellContactActor {
  std::string name;
  const TriMesh* mesh = nullptr;       // the actor's own vertices and faces (ShellActorPart::mesh)
  int firstVertex = 0;                 // the stacked id of its vertex 0
  std::vector<double> faceArea;        // rest area per face of *mesh
  ContactParams contact;
  ContactQuadrature quadrature = ContactQuadrature::Vertices;
  bool pointCloud = false;
  PointCloudColliderParams pointCloudCollider;
};

struct VolumeColliderPart {
  VolumeColliderPtr collider;
  ContactParams contact;
};

struct ShellContact {
  std::vector<VolumeContactTerms> volume;
  PointCloudTerms pointCloud;  // state null when no point-cloud contact
  bool empty() const { return volume.empty() && !pointCloud.state; }
  /// The narrowest ramp smoothing δ of any contact pair [m] (pairs combine by geometric mean, so no pair's δ is
  /// below the smallest of its actors'): the length over which a contact force can change from nothing to its
  /// penalty's full slope. 0 when empty.
  double narrowestRamp = 0.0;
  /// The step bounds' fraction (addShellContact's stepFraction).
  double stepFraction = 0.5;
  /// How finely a step must be divided so that a moving solid cannot pass through the shell between two of its
  /// parts: a Newton step sees the solid only where it is at the step's end, so a solid that moves, near the
  /// shell, by more than its thinnest half-width in one step can jump over a layer (measured: a capsule of
  /// radius 5 cm rising at 30 m/s went through a cloth at 60 Hz without touching it). In each part no solid of
  /// finite thickness moves near the shell by more than stepFraction of its thinnest half-width. Where that
  /// bound on its material's move asks for division, the solid's surface is looked at instead
  /// (energies/contact/surface_sweep.h): a part in which the signed distance at every sample point the solid may
  /// reach changes by at most as much is as safe, and a solid moving along its own surface (a box turning as a
  /// turntable, or sliding as a tray, under a cloth on its top) then divides less or nothing. The fewer parts of
  /// the two bounds are taken.
  struct SolidSweep {
    double parts = 1.0;        // the division needed (≥ 1; 1: none)
    std::string solid;         // the solid that needs the most (or, when none needs any, the first whose
                               // material's move asked for some; empty: none did)
    double travel = 0.0;       // its move near the shell over the whole step [m]
    double allowed = 0.0;      // its move allowed in one part [m]
    bool bySurface = false;    // parts came from the surface's sweep, fewer than its material's move asks for
  };
  /// From positions and velocities x, v (3N) at time t, for a step of h that may be divided into at most maxParts
  /// (the surface's sweep is sampled at up to 4 maxParts sub-times, at most 4096).
  SolidSweep solidSweep(const Eigen::VectorXd& x, const Eigen::VectorXd& v, double t, double h,
                        double maxParts = 64.0) const;
  /// Names of the contact terms (for timing splits).
  std::vector<std::string> termNames() const;
  /// The contact force on each volume actor from all shells at x (3N), each solid once, in the order of the
  /// volumes: the penalty's push with the solids where they are at time t (VolumeContactState::forceOnSolid), and,
  /// once a time step has begun, the Hunt–Crossley damping and friction of that step (the sums over the shell's
  /// vertices of those terms' gradients: what they push the shell with, the solid takes back).
  std::vector<std::pair<std::string, Eigen::Vector3d>> solidForces(const Eigen::VectorXd& x, double t) const;
  /// The volume actors solidForces names, in its order.
  std::vector<std::string> solidNames() const;
  /// The contact guards of a step's end (DynamicsOptions::contactGuardSolves): true when a sample lies deeper below
  /// a volume's surface than depthFraction × that pair's activation distance, or two interacting samples of the
  /// point cloud are closer than pairFraction × their contact distance 2r. x: 3N positions.
  bool guardsBroken(const Eigen::VectorXd& x, double depthFraction, double pairFraction) const;
  /// Seconds spent in the point-cloud broad phase so far.
  double broadPhaseSeconds() const { return pointCloud.state ? pointCloud.state->broadPhaseSeconds() : 0.0; }
};

/// Builds and adds the contact terms (see the file comment). rest: stacked rest positions (N × 3).
ShellContact addShellContact(Objective& objective, const std::vector<ShellContactActor>& actors,
                             const std::vector<VolumeColliderPart>& volumes, const Positions& rest, bool dynamic,
                             double stepFraction = 0.5);

}  // namespace jetshell
