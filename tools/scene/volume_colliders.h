// The scene's rigid volume actors as contact colliders (energies/contact/volume_collider.h): shape, placement
// and prescribed path. Input: validated VolumeActorParams (an SDF grid's file path already resolved). Output:
// one collider per actor, named after it. Throws InputError naming the actor for an unreadable grid file.
#pragma once

#include "energies/contact/volume_collider.h"
#include "tools/scene/actor_params.h"

namespace jetshell {

VolumeColliderPtr makeVolumeCollider(const VolumeActorParams& volume);

}  // namespace jetshell
