#include "tools/scene/volume_shape.h"

namespace jetshell {

VolumeShapePtr analyticVolumeShape(const VolumeActorParams& v) {
  switch (v.kind) {
    case VolumeActorParams::Kind::Plane: return makePlaneShape();
    case VolumeActorParams::Kind::Box: return makeBoxShape(v.halfExtents, v.edgeRadius);
    case VolumeActorParams::Kind::Sphere: return makeSphereShape(v.radius);
    case VolumeActorParams::Kind::Capsule: return makeCapsuleShape(v.radius, v.halfLength);
    case VolumeActorParams::Kind::SdfGrid: break;
  }
  return nullptr;
}

}  // namespace jetshell
