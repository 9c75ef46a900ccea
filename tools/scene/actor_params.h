// The spec's actor parameters: ShellActorParams and what it holds (transform, collider, contact; ContactParams
// and PointCloudColliderParams live in energies/contact/contact_params.h), plus the rigid volume actors (plane,
// box, sphere, capsule, signed-distance grid) shells collide with, static or moving on a prescribed path.
#pragma once

#include "energies/contact/contact_params.h"
#include "energies/contact/rigid_path.h"
#include "energies/contact/volume_shapes.h"
#include "energies/shell/material.h"
#include "tools/scene/shapes.h"

#include <Eigen/Geometry>

#include <cstdint>
#include <limits>
#include <string>
#include <vector>

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

/// A rigid volume actor shells collide with.
struct VolumeActorParams {
  enum class Kind { Plane, Box, Sphere, Capsule, SdfGrid };
  Kind kind = Kind::Plane;
  std::string name;
  std::string layer;
  /// Plane: the solid is z < 0 in local coordinates (normal +z). Box: centred at the local origin.
  /// Sphere: centred at the local origin.
  RigidTransform worldFromLocalTransform;
  Eigen::Vector3d halfExtents = Eigen::Vector3d::Constant(0.5);  // box, m
  double edgeRadius = 0.0;  // box: its edges and corners rounded with this radius, m (0: sharp)
  double radius = 0.5;                                            // sphere and capsule, m
  double halfLength = 0.5;    // capsule: half length of its axis segment along local z, m
  std::string sdfFile;        // SdfGrid: the grid file (energies/contact/sdf_grid.h), local coordinates
  std::int64_t sdfSamples = 0;  // SdfGrid: its sample count, as the scene reader found it (for the scene's bounds)
  /// SdfGrid: the shape the scene reader made of the file, shared by every actor that names it, and the box its
  /// samples span (local coordinates), so that a run reads the file once. Null for actors built otherwise, whose
  /// file is read when a run needs it.
  VolumeShapePtr sdfShape;
  Eigen::AlignedBox3d sdfBox;
  /// SdfGrid: a bound on the half-width of the solid's thinnest part [m] (sdfGridThinnestHalfWidth), by which
  /// contact coverage (tools/scene/contact_coverage.h) judges the grid. Infinite for actors built otherwise.
  double sdfThinnestHalfWidth = std::numeric_limits<double>::infinity();
  /// Prescribed motion from the transform at t = 0: constant velocity [m/s] and angular velocity [rad/s]
  /// (world axes, about the actor's origin), or keyframes (energies/contact/rigid_path.h: translations and turns
  /// of the placement at increasing times > 0), not both. Zero and none: static.
  Eigen::Vector3d velocity = Eigen::Vector3d::Zero();
  Eigen::Vector3d angularVelocity = Eigen::Vector3d::Zero();
  std::vector<RigidKeyframe> keyframes;
  ContactParams contact;
};

/// Throws InputError naming the field ("<where>.material.density = -1: ...") for any invalid parameter:
/// missing shape, material (see validate(ShellMaterialParams)), non-unit or non-finite transform, negative
/// contact or collider values.
void validate(const ShellActorParams& p, const std::string& where);
void validate(const VolumeActorParams& p, const std::string& where);
/// A box's edge radius: finite, >= 0 and at most its smallest half-extent (InputError naming `field`).
void checkEdgeRadius(double edgeRadius, const Eigen::Vector3d& halfExtents, const std::string& field);
void validate(const ContactParams& p, const std::string& where);

/// The actor's prescribed path (energies/contact/rigid_path.h): its placement, velocities and keyframes.
RigidPath rigidPath(const VolumeActorParams& p);

const char* toString(ColliderType t);
const char* toString(ActorBoundaryElementType t);
const char* toString(VolumeActorParams::Kind k);

}  // namespace jetshell
