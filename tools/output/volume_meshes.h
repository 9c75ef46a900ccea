// Triangle meshes of the rigid volume actors, for output and pictures only (planes are drawn as a square).
#pragma once

#include "core/mesh.h"
#include "tools/scene/actor_params.h"

namespace jetshell {

/// The surface of a volume actor in world coordinates. A plane becomes a square of half-size `planeHalfSize`
/// centred on the point of the plane nearest to `planeCenterHint` (the scene's centre, so the square sits under
/// the shells).
TriMesh volumeSurface(const VolumeActorParams& volume, double planeHalfSize, const Eigen::Vector3d& planeCenterHint);

}  // namespace jetshell
