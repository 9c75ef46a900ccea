#include "energies/contact/volume_shapes.h"

#include "core/mesh.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace jetshell {
namespace {

/// Distance to a point c (a sphere of radius `radius` about it): d = ‖p − c‖ − radius. `dropAxis` removes one
/// direction from the Hessian when c slides along it (a capsule's side).
SdfSample roundDistance(const Eigen::Vector3d& p, const Eigen::Vector3d& c, double radius, int dropAxis = -1) {
  SdfSample s;
  const Eigen::Vector3d v = p - c;
  const double n = v.norm();
  s.distance = n - radius;
  if (n < 1e-300) {  // at the centre: any direction; the Hessian is unbounded, report none
    s.gradient = Eigen::Vector3d::UnitZ();
    return s;
  }
  s.gradient = v / n;
  s.hessian = (Eigen::Matrix3d::Identity() - s.gradient * s.gradient.transpose()) / n;
  if (dropAxis >= 0) {
    s.hessian.row(dropAxis).setZero();
    s.hessian.col(dropAxis).setZero();
  }
  return s;
}

class PlaneShape : public VolumeShape {
 public:
  std::string kind() const override { return "plane"; }
  SdfSample signedDistance(const Eigen::Vector3d& p) const override {
    SdfSample s;
    s.distance = p.z();
    return s;
  }
  double thinnestHalfWidth() const override { return std::numeric_limits<double>::infinity(); }
};

class SphereShape : public VolumeShape {
 public:
  explicit SphereShape(double r) : r_(r) {}
  std::string kind() const override { return "sphere"; }
  SdfSample signedDistance(const Eigen::Vector3d& p) const override {
    return roundDistance(p, Eigen::Vector3d::Zero(), r_);
  }
  double thinnestHalfWidth() const override { return r_; }
  Eigen::Vector3d surfaceTurning(const Eigen::Vector3d&) const override { return Eigen::Vector3d::Zero(); }

 private:
  double r_;
};

class BoxShape : public VolumeShape {
 public:
  BoxShape(const Eigen::Vector3d& h, double r) : h_(h), r_(r), core_(h - Eigen::Vector3d::Constant(r)) {}
  std::string kind() const override { return "box"; }
  /// The distance to the core box (half-extents h − r) less r: a sharp box when r = 0.
  SdfSample signedDistance(const Eigen::Vector3d& p) const override {
    SdfSample s;
    Eigen::Vector3d q, sign;
    for (int i = 0; i < 3; ++i) {
      q[i] = std::abs(p[i]) - core_[i];
      sign[i] = p[i] < 0.0 ? -1.0 : 1.0;
    }
    if (q.maxCoeff() <= 0.0) {  // inside the core: distance to its nearest face
      int m = 0;
      s.distance = q.maxCoeff(&m) - r_;
      s.gradient = Eigen::Vector3d::Zero();
      s.gradient[m] = sign[m];
      return s;
    }
    const Eigen::Vector3d w = q.cwiseMax(0.0);  // outside the core: distance to its nearest face, edge or corner
    const double d = w.norm();
    s.distance = d - r_;
    s.gradient = sign.cwiseProduct(w) / d;
    s.hessian.setZero();
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j)
        if (w[i] > 0.0 && w[j] > 0.0) s.hessian(i, j) = ((i == j ? 1.0 : 0.0) - s.gradient[i] * s.gradient[j]) / d;
    return s;
  }
  double thinnestHalfWidth() const override { return h_.minCoeff(); }

 private:
  Eigen::Vector3d h_;
  double r_;
  Eigen::Vector3d core_;
};

class CapsuleShape : public VolumeShape {
 public:
  CapsuleShape(double r, double halfLength) : r_(r), l_(halfLength) {}
  std::string kind() const override { return "capsule"; }
  SdfSample signedDistance(const Eigen::Vector3d& p) const override {
    const double z = std::clamp(p.z(), -l_, l_);
    const bool side = std::abs(p.z()) < l_;
    return roundDistance(p, Eigen::Vector3d(0.0, 0.0, z), r_, side ? 2 : -1);
  }
  double thinnestHalfWidth() const override { return r_; }
  Eigen::Vector3d surfaceTurning(const Eigen::Vector3d& w) const override { return {w.x(), w.y(), 0.0}; }

 private:
  double r_, l_;
};

void requirePositive(double v, const char* what) {
  if (!(std::isfinite(v) && v > 0.0)) throw InputError(std::string(what) + " = " + std::to_string(v) + ": must be finite and > 0");
}

}  // namespace

VolumeShapePtr makePlaneShape() { return std::make_shared<PlaneShape>(); }
VolumeShapePtr makeSphereShape(double radius) {
  requirePositive(radius, "sphere radius");
  return std::make_shared<SphereShape>(radius);
}
VolumeShapePtr makeBoxShape(const Eigen::Vector3d& halfExtents, double edgeRadius) {
  for (int i = 0; i < 3; ++i) requirePositive(halfExtents[i], "box half extent");
  if (!(edgeRadius >= 0.0 && edgeRadius <= halfExtents.minCoeff()))
    throw InputError("box edgeRadius: must lie in [0, the smallest half extent]");
  return std::make_shared<BoxShape>(halfExtents, edgeRadius);
}
VolumeShapePtr makeCapsuleShape(double radius, double halfLength) {
  requirePositive(radius, "capsule radius");
  if (!(std::isfinite(halfLength) && halfLength >= 0.0)) throw InputError("capsule halfLength: must be finite and >= 0");
  return std::make_shared<CapsuleShape>(radius, halfLength);
}

}  // namespace jetshell
