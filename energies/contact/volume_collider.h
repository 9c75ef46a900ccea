// A rigid volume actor as contact sees it: a shape (energies/contact/volume_shapes.h) placed in the world on a
// prescribed path (energies/contact/rigid_path.h), static, moving at constant velocities or through keyframes.
//
// Input: a world point p and a time t. Output: the world signed distance sample (d, ∇d, ∇²d) of the shape in its
// frame at t (rotation R(t), origin c(t)), and the move over a step [t, t + h] of the solid's material at p (from
// the poses at both ends, exact whatever pieces of the path lie between), which friction uses as the collider's own
// slip.
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
  /// Where the solid's material point at p at time t has moved by t + h, less p (RigidPath::motion). The chord of
  /// a turn, and a keyframed stop or corner within the step, are exact (h times the material's velocity at t is
  /// not).
  Eigen::Vector3d materialMove(const Eigen::Vector3d& p, double t, double h) const;
  /// The part of a piece's angular velocity that moves the solid's surface (world axes; the shape's symmetry,
  /// VolumeShape::surfaceTurning, judged where the piece starts): what bounds the surface's sweep.
  Eigen::Vector3d surfaceTurning(const RigidPath::Piece& piece) const;
  /// The same solid on its path as an analysis run by `clock` reads it (RigidPath::readBy).
  std::shared_ptr<const VolumeCollider> readBy(PathClock clock) const;

 private:
  /// The signed distance at p of the shape placed with rotation R at origin c.
  SdfSample placed(const Eigen::Vector3d& p, const Eigen::Matrix3d& R, const Eigen::Vector3d& c) const;

  std::string name_;
  VolumeShapePtr shape_;
  RigidPath path_;
  Eigen::Matrix3d r0_;
  bool moving_ = false;
};

using VolumeColliderPtr = std::shared_ptr<const VolumeCollider>;

}  // namespace jetshell
