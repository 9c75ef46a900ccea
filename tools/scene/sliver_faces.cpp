#include "tools/scene/sliver_faces.h"

#include "core/format.h"
#include "core/topology.h"
#include "tools/scene/warning_list.h"

#include <cmath>
#include <limits>

namespace jetshell {

std::vector<std::string> sliverFaceWarnings(const Scene& scene, const std::vector<ActorBlock>& actors) {
  WarningList warnings;
  for (std::size_t a = 0; a < scene.shells.size() && a < actors.size(); ++a) {
    const TriMesh& mesh = actors[a].mesh;
    int slivers = 0, thinnestFace = -1;
    double thinnest = std::numeric_limits<double>::infinity(), thinnestEdge = 0.0;
    for (int f = 0; f < mesh.numFaces(); ++f) {
      const FaceShape shape = faceShape(mesh, f);
      const double longest2 = shape.longestSquared;
      const double ratio = shape.doubleArea / longest2;  // height / longest edge = (2 area / L) / L
      if (!(ratio < kSliverHeightRatio)) continue;
      ++slivers;
      if (ratio < thinnest) thinnest = ratio, thinnestFace = f, thinnestEdge = std::sqrt(longest2);
    }
    if (slivers == 0) continue;
    warnings.add([&] {
      return "shell actor '" + scene.shells[a].name + "': " + std::to_string(slivers) + " of its " +
             std::to_string(mesh.numFaces()) + " faces are slivers, lower than " +
             formatNumber("%g", kSliverHeightRatio) + " of their longest edge (the thinnest, face " +
             std::to_string(thinnestFace) + " counted from 0, " + formatNumber("%.3g", thinnest) + " of its " +
             formatNumber("%.3g", thinnestEdge) +
             " m edge): Newton slows down on such faces or stalls in its line search (fewer faces across the narrow "
             "direction, or a remeshed surface, widen them)";
    });
  }
  return std::move(warnings).finish("shell actors with sliver faces");
}

}  // namespace jetshell
