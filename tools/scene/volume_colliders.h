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

/// The shapes of SDF grid files so far, by resolved path: actors that name one file share its shape (a shape is
/// immutable; each collider places it on its own path), so the grid is held once. An actor from the scene reader
/// brings the reader's shape (VolumeActorParams::sdfShape), so the file is read once a run; one built through the
/// API is read here. The grids' samples are counted (the reader's counts, or as read here) and bounded together by
/// InputLimits::maxSdfSamples, here as well as in the scene reader: a scene built through the API was not counted.
struct SdfShapes {
  std::map<std::string, VolumeShapePtr> byFile;
  std::int64_t samples = 0;
};

VolumeColliderPtr makeVolumeCollider(const VolumeActorParams& volume, SdfShapes* shapes = nullptr);

}  // namespace jetshell
