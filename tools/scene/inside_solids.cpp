#include "tools/scene/inside_solids.h"

#include "core/format.h"
#include "core/topology.h"
#include "tools/scene/volume_shape.h"
#include "tools/scene/warning_list.h"

namespace jetshell {

std::vector<std::string> insideSolidWarnings(const Scene& scene, const std::vector<ActorBlock>& actors) {
  if (scene.volumes.empty()) return {};
  WarningList warnings;
  std::vector<VolumeShapePtr> shapes;  // each made once, not once per shell actor
  for (const VolumeActorParams& v : scene.volumes)
    shapes.push_back(v.kind == VolumeActorParams::Kind::SdfGrid ? v.sdfShape : analyticVolumeShape(v));
  for (std::size_t a = 0; a < scene.shells.size() && a < actors.size(); ++a) {
    const ActorBlock& block = actors[a];
    const double onSurface = 1e-9 * meanEdgeLength(block.mesh, block.topology);
    for (std::size_t k = 0; k < scene.volumes.size(); ++k) {
      if (!shapes[k]) continue;
      const RigidTransform& place = scene.volumes[k].worldFromLocalTransform;
      const Eigen::Quaterniond toLocal = place.rotation.normalized().conjugate();
      int inside = 0, deepestVertex = -1;
      double deepest = 0.0;
      for (int v = 0; v < block.numVertices; ++v) {
        const Eigen::Vector3d p = block.mesh.V.row(v).transpose();
        const double d = shapes[k]->signedDistance(toLocal * (p - place.translation)).distance;
        if (!(d < -onSurface)) continue;
        ++inside;
        if (d < deepest) deepest = d, deepestVertex = v;
      }
      if (inside == 0) continue;
      warnings.add([&] {
        const Eigen::Vector3d at = block.mesh.V.row(deepestVertex).transpose();
        return "shell actor '" + scene.shells[a].name + "' starts inside volume actor '" + scene.volumes[k].name +
               "': " + std::to_string(inside) + " of its " + std::to_string(block.numVertices) +
               " vertices lie inside it, the deepest " + formatNumber("%.3g", -deepest) + " m (vertex " +
               std::to_string(deepestVertex) + ", counted from 0, at (" + formatNumber("%.6g", at.x()) + ", " +
               formatNumber("%.6g", at.y()) + ", " + formatNumber("%.6g", at.z()) +
               ")); the contact penalty pushes them out in the first steps (start the shell and the solid apart, "
               "and move the solid in)";
      });
    }
  }
  return std::move(warnings).finish("pairs of a shell actor that starts inside a volume actor");
}

}  // namespace jetshell
