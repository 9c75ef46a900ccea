// A rigid volume actor as contact sees it: a shape (energies/contact/volume_shapes.h) placed in the world on a
// prescribed path (energies/contact/rigid_path.h), static, moving at constant velocities or through keyframes.
//
// Input: a world point p and a time t. Output: the world signed distance sample (d, ∇d, ∇²d) of the shape in its
// frame at t (rotation R(t), origin c(t)), and the velocity of the solid's material at p (v(t) + ω(t) × (p − c(t)),
// the velocities of the path's piece at t), which friction uses as the collider's own slip.
#pragma once

#include "energies/contact/rigid_path.h"
#include "energies/contact/volume_shapes.h"

#include <Eigen/Geometry>

#include <memory>
#include <string>

namespace jetshell {

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
  /// The same solid held still where it is at t = 0 (the same shape, no velocity, no keyframes).
  std::shared_ptr<const VolumeCollider> heldAtStart() const;

 private:
  std::string name_;
  VolumeShapePtr shape_;
  RigidPath path_;
  Eigen::Matrix3d r0_;
  bool moving_ = false;
};

using VolumeColliderPtr = std::shared_ptr<const VolumeCollider>;

}  // namespace jetshell
