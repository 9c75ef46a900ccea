#include "energies/contact/volume_collider.h"

#include "core/mesh.h"

#include <cmath>

namespace jetshell {

Eigen::Matrix3d RigidPath::rotationAt(double t) const {
  const Eigen::Matrix3d r0 = rotation.normalized().toRotationMatrix();
  const double w = angularVelocity.norm();
  if (w == 0.0) return r0;
  return Eigen::AngleAxisd(w * t, angularVelocity / w).toRotationMatrix() * r0;
}

VolumeCollider::VolumeCollider(std::string name, VolumeShapePtr shape, RigidPath path)
    : name_(std::move(name)), shape_(std::move(shape)), path_(std::move(path)) {
  if (!shape_) throw InputError("volume collider '" + name_ + "': no shape");
  if (!path_.origin.allFinite() || !path_.velocity.allFinite() || !path_.angularVelocity.allFinite() ||
      !path_.rotation.coeffs().allFinite() || path_.rotation.norm() == 0.0)
    throw InputError("volume collider '" + name_ + "': path must be finite with a non-zero rotation");
  r0_ = path_.rotation.normalized().toRotationMatrix();
}

SdfSample VolumeCollider::query(const Eigen::Vector3d& p, double t) const {
  const bool moving = !path_.isStatic();
  const Eigen::Matrix3d R = moving ? path_.rotationAt(t) : r0_;
  const Eigen::Vector3d c = moving ? path_.originAt(t) : path_.origin;
  SdfSample s = shape_->signedDistance(R.transpose() * (p - c));
  s.gradient = R * s.gradient;
  s.hessian = R * s.hessian * R.transpose();
  return s;
}

Eigen::Vector3d VolumeCollider::velocityAt(const Eigen::Vector3d& p, double t) const {
  if (path_.isStatic()) return Eigen::Vector3d::Zero();
  return path_.velocity + path_.angularVelocity.cross(p - path_.originAt(t));
}

std::shared_ptr<const VolumeCollider> VolumeCollider::heldAtStart() const {
  RigidPath held = path_;
  held.velocity.setZero();
  held.angularVelocity.setZero();
  return std::make_shared<VolumeCollider>(name_, shape_, held);
}

}  // namespace jetshell
