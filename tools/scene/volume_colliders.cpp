#include "tools/scene/volume_colliders.h"

#include "core/input_limits.h"
#include "core/mesh.h"
#include "energies/contact/sdf_grid.h"
#include "tools/scene/volume_shape.h"

namespace jetshell {

namespace {

/// The actor's grid as a shape: the scene reader's, or read from its file (actors built otherwise).
VolumeShapePtr sdfShape(const VolumeActorParams& v, SdfShapes* shapes) {
  if (shapes)
    if (const auto found = shapes->byFile.find(v.sdfFile); found != shapes->byFile.end()) return found->second;
  VolumeShapePtr shape = v.sdfShape;
  std::int64_t samples = v.sdfSamples;
  SdfGrid grid;
  if (!shape) {
    grid = readSdfGrid(v.sdfFile);
    samples = static_cast<std::int64_t>(grid.values.size());
  }
  if (shapes) {
    shapes->samples += samples;
    const std::int64_t limit = inputLimits().maxSdfSamples;
    if (shapes->samples > limit)
      throw InputError(v.sdfFile + ": samples of all SDF grids of the scene = " + std::to_string(shapes->samples) +
                       ": too large (at most " + std::to_string(limit) + ")");
  }
  if (!shape) shape = makeSdfGridShape(std::move(grid));
  if (shapes) shapes->byFile.emplace(v.sdfFile, shape);
  return shape;
}

}  // namespace

VolumeColliderPtr makeVolumeCollider(const VolumeActorParams& v, SdfShapes* shapes) {
  const VolumeShapePtr shape =
      v.kind == VolumeActorParams::Kind::SdfGrid ? sdfShape(v, shapes) : analyticVolumeShape(v);
  return std::make_shared<VolumeCollider>(v.name, shape, rigidPath(v));
}

}  // namespace jetshell
