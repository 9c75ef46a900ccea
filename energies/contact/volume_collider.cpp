#include "energies/contact/volume_collider.h"

#include "core/mesh.h"

namespace jetshell {

VolumeCollider::VolumeCollider(std::string name, VolumeShapePtr shape, RigidPath path)
    : name_(std::move(name)), shape_(std::move(shape)), path_(std::move(path)) {
  if (!shape_) throw InputError("volume collider '" + name_ + "': no shape");
  path_.validate("volume collider '" + name_ + "'");
  r0_ = path_.rotation.normalized().toRotationMatrix();
  moving_ = !path_.isStatic();
}

SdfSample VolumeCollider::query(const Eigen::Vector3d& p, double t) const {
  const Eigen::Matrix3d R = moving_ ? path_.rotationAt(t) : r0_;
  const Eigen::Vector3d c = moving_ ? path_.originAt(t) : path_.origin;
  SdfSample s = shape_->signedDistance(R.transpose() * (p - c));
  s.gradient = R * s.gradient;
  s.hessian = R * s.hessian * R.transpose();
  return s;
}

Eigen::Vector3d VolumeCollider::velocityAt(const Eigen::Vector3d& p, double t) const {
  if (!moving_) return Eigen::Vector3d::Zero();
  const RigidPath::Piece piece = path_.pieceAt(t);
  return piece.velocity + piece.angularVelocity.cross(p - path_.originAt(t));
}

std::shared_ptr<const VolumeCollider> VolumeCollider::heldAtStart() const {
  RigidPath held = path_;
  held.velocity.setZero();
  held.angularVelocity.setZero();
  held.keyframes.clear();  // they start from the placement
  return std::make_shared<VolumeCollider>(name_, shape_, held);
}

}  // namespace jetshell
