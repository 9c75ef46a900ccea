#include "tools/scene/volume_colliders.h"

#include "core/input_limits.h"
#include "core/mesh.h"
#include "energies/contact/sdf_grid.h"
#include "tools/scene/volume_shape.h"

namespace jetshell {

namespace {

VolumeShapePtr sdfShape(const std::string& file, SdfShapes* shapes) {
  if (shapes)
    if (const auto found = shapes->byFile.find(file); found != shapes->byFile.end()) return found->second;
  SdfGrid grid = readSdfGrid(file);
  if (shapes) {
    shapes->samples += static_cast<std::int64_t>(grid.values.size());
    const std::int64_t limit = inputLimits().maxSdfSamples;
    if (shapes->samples > limit)
      throw InputError(file + ": samples of all SDF grids of the scene = " + std::to_string(shapes->samples) +
                       ": too large (at most " + std::to_string(limit) + ")");
  }
  VolumeShapePtr shape = makeSdfGridShape(std::move(grid));
  if (shapes) shapes->byFile.emplace(file, shape);
  return shape;
}

}  // namespace

VolumeColliderPtr makeVolumeCollider(const VolumeActorParams& v, SdfShapes* shapes) {
  const VolumeShapePtr shape =
      v.kind == VolumeActorParams::Kind::SdfGrid ? sdfShape(v.sdfFile, shapes) : analyticVolumeShape(v);
  return std::make_shared<VolumeCollider>(v.name, shape, rigidPath(v));
}

}  // namespace jetshell
