#include "tools/scene/volume_colliders.h"

#include "energies/contact/sdf_grid.h"

namespace jetshell {

namespace {

VolumeShapePtr sdfShape(const std::string& file, SdfShapes* shapes) {
  if (shapes)
    if (const auto found = shapes->find(file); found != shapes->end()) return found->second;
  VolumeShapePtr shape = makeSdfGridShape(readSdfGrid(file));
  if (shapes) shapes->emplace(file, shape);
  return shape;
}

}  // namespace

VolumeColliderPtr makeVolumeCollider(const VolumeActorParams& v, SdfShapes* shapes) {
  VolumeShapePtr shape;
  switch (v.kind) {
    case VolumeActorParams::Kind::Plane: shape = makePlaneShape(); break;
    case VolumeActorParams::Kind::Box: shape = makeBoxShape(v.halfExtents); break;
    case VolumeActorParams::Kind::Sphere: shape = makeSphereShape(v.radius); break;
    case VolumeActorParams::Kind::Capsule: shape = makeCapsuleShape(v.radius, v.halfLength); break;
    case VolumeActorParams::Kind::SdfGrid: shape = sdfShape(v.sdfFile, shapes); break;
  }
  RigidPath path;
  path.origin = v.worldFromLocalTransform.translation;
  path.rotation = v.worldFromLocalTransform.rotation;
  path.velocity = v.velocity;
  path.angularVelocity = v.angularVelocity;
  return std::make_shared<VolumeCollider>(v.name, shape, path);
}

}  // namespace jetshell
