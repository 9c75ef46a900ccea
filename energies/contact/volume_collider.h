// A rigid volume actor as contact sees it: a shape (energies/contact/volume_shapes.h) placed in the world on a
// prescribed path, static or moving.
//
// Path: at time t the shape's frame has rotation R(t) = Rot(ω t) · R₀ (ω: constant angular velocity [rad/s],
// world axes) and origin c(t) = c₀ + v t (v: constant velocity [m/s]). Input: a world point p and a time t.
// Output: the world signed distance sample (d, ∇d, ∇²d) and the velocity of the solid's material at p
// (v + ω × (p − c(t))), which friction uses as the collider's own slip.
#pragma once

#include "energies/contact/volume_shapes.h"

#include <Eigen/Geometry>

#include <memory>
#include <string>

namespace jetshell {

struct RigidPath {
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();                // c₀ [m]
  Eigen::Quaterniond rotation = Eigen::Quaterniond::Identity();    // R₀
  Eigen::Vector3d velocity = Eigen::Vector3d::Zero();              // v [m/s]
  Eigen::Vector3d angularVelocity = Eigen::Vector3d::Zero();       // ω [rad/s]

  bool isStatic() const { return velocity.squaredNorm() == 0.0 && angularVelocity.squaredNorm() == 0.0; }
  Eigen::Matrix3d rotationAt(double t) const;
  Eigen::Vector3d originAt(double t) const { return origin + t * velocity; }
};

class VolumeCollider {
 public:
  VolumeCollider(std::string name, VolumeShapePtr shape, RigidPath path);
  const std::string& name() const { return name_; }
  const VolumeShape& shape() const { return *shape_; }
  const RigidPath& path() const { return path_; }

  /// World signed distance at p and time t. Thread-safe.
  SdfSample query(const Eigen::Vector3d& p, double t) const;
  /// Velocity of the solid's material point at p, time t.
  Eigen::Vector3d velocityAt(const Eigen::Vector3d& p, double t) const;
  /// The same solid held still where it is at t = 0 (the same shape, no velocity, no angular velocity).
  std::shared_ptr<const VolumeCollider> heldAtStart() const;

 private:
  std::string name_;
  VolumeShapePtr shape_;
  RigidPath path_;
  Eigen::Matrix3d r0_;
};

using VolumeColliderPtr = std::shared_ptr<const VolumeCollider>;

}  // namespace jetshell
