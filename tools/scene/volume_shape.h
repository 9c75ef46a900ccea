// The shape of a rigid volume actor from its parameters: the half-space, a box, a ball or a capsule
// (energies/contact/volume_shapes.h). An SDF grid's shape comes from its file instead (tools/scene/volume_colliders.h).
#pragma once

#include "energies/contact/volume_shapes.h"
#include "tools/scene/actor_params.h"

namespace jetshell {

/// Null for an SDF grid.
VolumeShapePtr analyticVolumeShape(const VolumeActorParams& volume);

}  // namespace jetshell
