#include "tools/scene/actor_params.h"

#include "core/format.h"
#include "core/input_limits.h"
#include "tools/scene/checks.h"

namespace jetshell {

RigidTransform RigidTransform::fromAxisAngle(const Eigen::Vector3d& axis, double angleRadians,
                                             const Eigen::Vector3d& translation) {
  check::nonZero(axis, "rotation axis");
  check::finite(angleRadians, "rotation angle");
  RigidTransform t;
  t.rotation = Eigen::Quaterniond(Eigen::AngleAxisd(angleRadians, axis.normalized()));
  t.translation = translation;
  return t;
}

namespace {

void validate(const RigidTransform& t, const std::string& where) {
  check::finite(t.translation, where + ".translation");
  check::normAtMost(t.translation, inputLimits().maxDistance, where + ".translation");
  const double n = t.rotation.norm();
  if (!(std::abs(n - 1.0) < 1e-9)) check::fail(where + ".rotation (quaternion norm)", n, "must be 1");
}

}  // namespace

void validate(const ContactParams& p, const std::string& where) {
  check::nonNegative(p.penaltyStiffness, where + ".penaltyStiffness");
  check::nonNegative(p.activationDistance, where + ".activationDistance");
  check::positive(p.smoothingDistance, where + ".smoothingDistance");
  check::nonNegative(p.huntCrossleyDamping, where + ".huntCrossleyDamping");
  check::nonNegative(p.frictionCoefficient, where + ".frictionCoefficient");
  check::positive(p.frictionSlipVelocity, where + ".frictionSlipVelocity");
}

void validate(const ShellActorParams& p, const std::string& where) {
  if (!p.shape) throw InputError(where + ".shape: missing (required; create it with CreateTriMeshShape)");
  validate(p.worldFromLocalTransform, where + ".worldFromLocalTransform");
  jetshell::validate(p.material, where + ".material");
  validate(p.contact, where + ".contact");
  check::positive(p.pointCloudCollider.radius, where + ".pointCloudCollider.radius");
  if (p.pointCloudCollider.radius < kMinPointCloudRadius)
    check::fail(where + ".pointCloudCollider.radius", p.pointCloudCollider.radius,
                "too small (at least 1e-6 m: the broad phase's cells are this wide)");
  check::nonNegative(p.pointCloudCollider.selfContactExclusionRatio,
                     where + ".pointCloudCollider.selfContactExclusionRatio");
}

void checkEdgeRadius(double edgeRadius, const Eigen::Vector3d& halfExtents, const std::string& field) {
  check::nonNegative(edgeRadius, field);
  if (edgeRadius > halfExtents.minCoeff())
    check::fail(field, edgeRadius,
                "must be at most the smallest half extent (" + formatNumber("%g", halfExtents.minCoeff()) + ")");
}

void validate(const VolumeActorParams& p, const std::string& where) {
  validate(p.worldFromLocalTransform, where + ".worldFromLocalTransform");
  const double most = inputLimits().maxDistance;
  if (p.kind == VolumeActorParams::Kind::Box) {
    for (int c = 0; c < 3; ++c) {
      const std::string field = where + ".halfExtents[" + std::to_string(c) + "]";
      check::positive(p.halfExtents[c], field);
      check::atMostReal(p.halfExtents[c], most, field);
    }
    checkEdgeRadius(p.edgeRadius, p.halfExtents, where + ".edgeRadius");
  }
  if (p.kind == VolumeActorParams::Kind::Sphere || p.kind == VolumeActorParams::Kind::Capsule) {
    check::positive(p.radius, where + ".radius");
    check::atMostReal(p.radius, most, where + ".radius");
  }
  if (p.kind == VolumeActorParams::Kind::Capsule) {
    check::nonNegative(p.halfLength, where + ".halfLength");
    check::atMostReal(p.halfLength, most, where + ".halfLength");
  }
  if (p.kind == VolumeActorParams::Kind::SdfGrid && p.sdfFile.empty())
    throw InputError(where + ".sdfFile: missing (required for an SDF grid)");
  check::finite(p.velocity, where + ".velocity");
  check::normAtMost(p.velocity, most, where + ".velocity");
  check::finite(p.angularVelocity, where + ".angularVelocity");
  check::normAtMost(p.angularVelocity, inputLimits().maxAngularVelocity, where + ".angularVelocity");
  check::atMost(static_cast<std::int64_t>(p.keyframes.size()), inputLimits().maxKeyframes, where + ".keyframes");
  for (std::size_t k = 0; k < p.keyframes.size(); ++k)
    check::normAtMost(p.keyframes[k].translation, inputLimits().maxDistance,
                      where + ".keyframes[" + std::to_string(k) + "].translation");
  rigidPath(p).validate(where);
  validate(p.contact, where + ".contact");
}

RigidPath rigidPath(const VolumeActorParams& p) {
  RigidPath path;
  path.origin = p.worldFromLocalTransform.translation;
  path.rotation = p.worldFromLocalTransform.rotation;
  path.velocity = p.velocity;
  path.angularVelocity = p.angularVelocity;
  path.keyframes = p.keyframes;
  return path;
}

const char* toString(ColliderType t) { return t == ColliderType::PointCloud ? "PointCloud" : "None"; }

const char* toString(ActorBoundaryElementType t) {
  switch (t) {
    case ActorBoundaryElementType::Default: return "Default";
    case ActorBoundaryElementType::Vertices: return "Vertices";
    case ActorBoundaryElementType::FaceCentroids: return "FaceCentroids";
    case ActorBoundaryElementType::FaceThreePoint: return "FaceThreePoint";
  }
  return "?";
}

const char* toString(VolumeActorParams::Kind k) {
  switch (k) {
    case VolumeActorParams::Kind::Plane: return "plane";
    case VolumeActorParams::Kind::Box: return "box";
    case VolumeActorParams::Kind::Sphere: return "sphere";
    case VolumeActorParams::Kind::Capsule: return "capsule";
    case VolumeActorParams::Kind::SdfGrid: return "sdfGrid";
  }
  return "?";
}

}  // namespace jetshell
