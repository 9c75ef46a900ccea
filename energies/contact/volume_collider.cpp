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
  if (!moving_) return placed(p, r0_, path_.origin);
  const RigidPath::State state = path_.stateAt(t);
  return placed(p, state.rotation, state.origin);
}

SdfSample VolumeCollider::placed(const Eigen::Vector3d& p, const Eigen::Matrix3d& R, const Eigen::Vector3d& c) const {
  SdfSample s = shape_->signedDistance(R.transpose() * (p - c));
  s.gradient = R * s.gradient;
  s.hessian = R * s.hessian * R.transpose();
  return s;
}

Eigen::Vector3d VolumeCollider::materialMove(const Eigen::Vector3d& p, double t, double h) const {
  if (!moving_) return Eigen::Vector3d::Zero();
  return path_.motion(t, t + h)(p) - p;
}

Eigen::Vector3d VolumeCollider::surfaceTurning(const RigidPath::Piece& piece) const {
  const Eigen::Matrix3d R = path_.rotationAt(piece.start);
  return R * shape_->surfaceTurning(R.transpose() * piece.angularVelocity);
}

std::shared_ptr<const VolumeCollider> VolumeCollider::readBy(PathClock clock) const {
  return std::make_shared<VolumeCollider>(name_, shape_, path_.readBy(clock));
}

}  // namespace jetshell
