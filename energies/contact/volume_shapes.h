// Signed distance functions of the rigid volume actors' shapes, in the shape's local frame.
//
// Input: a point p (local coordinates, m). Output: an SdfSample: the signed distance d (negative inside the
// solid), its gradient ∇d (the outward unit normal where d is smooth) and its Hessian ∇²d (3×3), exact at p.
// The contact energies feed these into a second-order model of d around p (energies/contact/sdf_model.h),
// so their Jet derivatives are exact wherever d is twice differentiable.
// Shapes: plane (the half-space z < 0, normal +z), sphere (centre at the origin), box (centred, half-extents; its
// edges and corners optionally rounded: the points within a radius r of the box of half-extents h − r),
// capsule (the points within `radius` of the segment from (0,0,−halfLength) to (0,0,+halfLength)), and a
// sampled grid read from a file (energies/contact/sdf_grid.h).
#pragma once

#include <Eigen/Core>

#include <memory>
#include <string>

namespace jetshell {

struct SdfSample {
  double distance = 0.0;
  Eigen::Vector3d gradient = Eigen::Vector3d::UnitZ();
  Eigen::Matrix3d hessian = Eigen::Matrix3d::Zero();
};

class VolumeShape {
 public:
  virtual ~VolumeShape() = default;
  virtual std::string kind() const = 0;
  /// Thread-safe: called concurrently by the element loops.
  virtual SdfSample signedDistance(const Eigen::Vector3d& p) const = 0;
  /// Half the width of the solid's thinnest part [m] (infinite for the half-space): a point that moves less than
  /// this from outside cannot come out on the far side, so contact's step bound allows at least a fraction of it.
  virtual double thinnestHalfWidth() const = 0;
  /// The part of an angular velocity (local axes) that moves the solid's surface: none of a rotation about an
  /// axis of symmetry through the origin (a ball's any axis, a capsule's own), which turns the solid in place.
  virtual Eigen::Vector3d surfaceTurning(const Eigen::Vector3d& angularVelocity) const { return angularVelocity; }
};

using VolumeShapePtr = std::shared_ptr<const VolumeShape>;

/// The half-space z < 0.
VolumeShapePtr makePlaneShape();
/// A ball of the given radius (> 0) at the origin.
VolumeShapePtr makeSphereShape(double radius);
/// An axis-aligned box with the given half-extents (> 0) centred at the origin, its edges and corners rounded with
/// edgeRadius (0: sharp; at most the smallest half-extent, where the box becomes a capsule, a ball or a slab with
/// rounded rims). A rounded edge has the curvature 1/edgeRadius that a sharp one lacks, so a shell folded over it
/// has a smooth distance to settle on.
VolumeShapePtr makeBoxShape(const Eigen::Vector3d& halfExtents, double edgeRadius = 0.0);
/// A capsule along local z: radius > 0, half length of its axis segment >= 0.
VolumeShapePtr makeCapsuleShape(double radius, double halfLength);

}  // namespace jetshell
