// The spec's actor parameters: ShellActorParams and what it holds (transform, collider, contact), plus the rigid
// volume actors (plane, box, sphere) shells can meet.
//
// Contact is stored and validated so scenes can state it, but no contact or collider term exists yet: a scene
// that asks for contact runs without it and says so (see tools/scene/scene.h, Scene::warnings()).
#pragma once

#include "energies/shell/material.h"
#include "tools/scene/shapes.h"

#include <Eigen/Geometry>

#include <string>

namespace jetshell {

/// A rigid transform x_world = rotation · x_local + translation (the spec's RT; identity by default).
struct RigidTransform {
  Eigen::Quaterniond rotation = Eigen::Quaterniond::Identity();
  Eigen::Vector3d translation = Eigen::Vector3d::Zero();
  Eigen::Vector3d apply(const Eigen::Vector3d& p) const { return rotation * p + translation; }
  /// A rotation by angleRadians about axis (need not be unit length; must be non-zero).
  static RigidTransform fromAxisAngle(const Eigen::Vector3d& axis, double angleRadians,
                                      const Eigen::Vector3d& translation = Eigen::Vector3d::Zero());
};

/// Shell-to-shell contact participation.
enum class ColliderType { PointCloud, None };

/// Quadrature that samples contact points on a shell surface.
enum class ActorBoundaryElementType { Default, Vertices, FaceCentroids, FaceThreePoint };

/// Contact with volume actors: penalty on the signed distance with a C²-smoothed ramp, Hunt–Crossley normal
/// damping, regularized Coulomb friction (which also applies to shell–shell contact). Defaults from the spec.
struct ContactParams {
  double penaltyStiffness = 1e9;       // Pa/m, k
  double activationDistance = 0.005;   // m, ε
  double smoothingDistance = 0.001;    // m, δ
  double huntCrossleyDamping = 0.0;    // s/m
  double frictionCoefficient = 0.5;    // μ
  double frictionSlipVelocity = 0.01;  // m/s, V_f
};

/// Point-cloud collider of a shell: spheres of `radius` at the contact samples.
struct PointCloudColliderParams {
  double radius = 0.01;                    // m
  bool selfContact = false;
  double selfContactExclusionRatio = 1.5;  // samples closer than ratio·radius in the rest shape never collide
};

/// The spec's ShellActorParams, with its defaults.
struct ShellActorParams {
  std::string name;
  std::string layer;
  RigidTransform worldFromLocalTransform;
  ShapeHandle shape;  // required
  ShellMaterialParams material;
  ColliderType colliderType = ColliderType::PointCloud;
  ContactParams contact;
  PointCloudColliderParams pointCloudCollider;
  bool hasGravity = true;
  ActorBoundaryElementType contactElementType = ActorBoundaryElementType::Default;
};

/// A rigid, static volume actor shells can rest on.
struct VolumeActorParams {
  enum class Kind { Plane, Box, Sphere };
  Kind kind = Kind::Plane;
  std::string name;
  std::string layer;
  /// Plane: the solid is z < 0 in local coordinates (normal +z). Box: centred at the local origin.
  /// Sphere: centred at the local origin.
  RigidTransform worldFromLocalTransform;
  Eigen::Vector3d halfExtents = Eigen::Vector3d::Constant(0.5);  // box, m
  double radius = 0.5;                                            // sphere, m
  ContactParams contact;
};

/// Throws InputError naming the field ("<where>.material.density = -1: ...") for any invalid parameter:
/// missing shape, material (see validate(ShellMaterialParams)), non-unit or non-finite transform, negative
/// contact or collider values.
void validate(const ShellActorParams& p, const std::string& where);
void validate(const VolumeActorParams& p, const std::string& where);
void validate(const ContactParams& p, const std::string& where);

const char* toString(ColliderType t);
const char* toString(ActorBoundaryElementType t);
const char* toString(VolumeActorParams::Kind k);

}  // namespace jetshell
