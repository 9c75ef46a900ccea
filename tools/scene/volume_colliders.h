// The scene's rigid volume actors as contact colliders (energies/contact/volume_collider.h): shape, placement
// and prescribed path. Input: validated VolumeActorParams (an SDF grid's file path already resolved). Output:
// one collider per actor, named after it. Throws InputError naming the actor for an unreadable grid file.
#pragma once

#include "energies/contact/volume_collider.h"
#include "tools/scene/actor_params.h"

#include <cstdint>
#include <map>
#include <string>

namespace jetshell {

/// The shapes made from SDF grid files so far, by resolved path: actors that name one file share its shape (a
/// shape is immutable; each collider places it on its own path), so the grid is read and held once. The grids'
/// samples are counted as they are read and bounded together by InputLimits::maxSdfSamples, here as well as in
/// the scene reader: a scene built through the API was not counted, and a file replaced after the scene was read
/// is counted as it is.
struct SdfShapes {
  std::map<std::string, VolumeShapePtr> byFile;
  std::int64_t samples = 0;
};

VolumeColliderPtr makeVolumeCollider(const VolumeActorParams& volume, SdfShapes* shapes = nullptr);

}  // namespace jetshell
