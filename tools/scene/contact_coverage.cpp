#include "tools/scene/contact_coverage.h"

#include "core/format.h"
#include "energies/contact/contact_params.h"
#include "tools/scene/volume_shape.h"
#include "tools/scene/warning_list.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace jetshell {

namespace {

std::string metres(double x) { return formatNumber("%.3g", x) + " m"; }

/// Half the width of the solid's thinnest part, as its shape states it; infinite for the half-space. An SDF grid
/// states none: it is judged by a bound from its samples (the thinnest of its ridges, sdfGridThinnestHalfWidth),
/// which errs towards the wide, so a grid is named only for a part that is thin.
double thinnestHalfWidth(const VolumeActorParams& v) {
  if (v.kind == VolumeActorParams::Kind::SdfGrid) return v.sdfThinnestHalfWidth;
  const VolumeShapePtr shape = analyticVolumeShape(v);
  return shape ? shape->thinnestHalfWidth() : std::numeric_limits<double>::infinity();
}

}  // namespace

std::vector<std::string> contactCoverageWarnings(const Scene& scene, const std::vector<ActorBlock>& actors) {
  WarningList warnings;
  const double toMiddle = 1.0 / std::sqrt(3.0);  // a face's middle from its corners, per edge length
  // Point clouds interact when two actors have one, or one has self-contact.
  int clouds = 0;
  bool self = false;
  double smallest = std::numeric_limits<double>::infinity();
  for (const ShellActorParams& s : scene.shells)
    if (s.colliderType == ColliderType::PointCloud) {
      ++clouds;
      self = self || s.pointCloudCollider.selfContact;
      smallest = std::min(smallest, s.pointCloudCollider.radius);
    }
  const bool pointContact = clouds >= 2 || self;
  std::vector<double> thinnest;  // per volume actor, its shape made once (not once per shell actor)
  for (const VolumeActorParams& v : scene.volumes) thinnest.push_back(thinnestHalfWidth(v));
  for (std::size_t a = 0; a < scene.shells.size() && a < actors.size(); ++a) {
    const ShellActorParams& s = scene.shells[a];
    const double gap = toMiddle * meanEdgeLength(actors[a].mesh, actors[a].topology);
    if (!(gap > 0.0)) continue;
    if (pointContact && s.colliderType == ColliderType::PointCloud) {
      const double r = s.pointCloudCollider.radius;
      if (gap > r + smallest)
        warnings.add([&] {
          return "shell actor '" + s.name + "': point-cloud samples of radius " + metres(r) +
                 " at vertices a mean edge of " + metres(gap / toMiddle) + " apart leave a gap " + metres(gap) +
                 " from the corners in the middle of a face, which a sample of radius " + metres(smallest) +
                 " passes through untouched (radii that add up to " + metres(gap) + ", or a finer mesh, close it)";
        });
    }
    const bool threePoint = s.contactElementType == ActorBoundaryElementType::FaceThreePoint;
    const double sampleGap = threePoint ? 0.5 * gap : gap;
    for (std::size_t k = 0; k < scene.volumes.size(); ++k) {
      const VolumeActorParams& v = scene.volumes[k];
      const double w = thinnest[k];
      const double reach = w + combine(s.contact, v.contact).activationDistance;
      if (!(sampleGap > reach)) continue;
      const bool grid = v.kind == VolumeActorParams::Kind::SdfGrid;
      warnings.add([&] {
        return "volume actor '" + v.name + "' (" +
               (grid ? "an SDF grid, thinnest half-width at most " + metres(w) : "thinnest half-width " + metres(w)) +
               ") fits between the contact samples of shell actor '" + s.name + "' (" +
               (threePoint ? "three points a face" : "at its vertices or face centroids") + ", about " +
               metres(sampleGap) + " from a face's middle, beyond its reach of " + metres(reach) +
               "): it can pass through the shell unfelt (" +
               (threePoint ? "a finer mesh" : "\"contactElementType\": \"FaceThreePoint\" or a finer mesh") +
               " closes the gap)";
      });
    }
  }
  return std::move(warnings).finish("contact pairs whose samples are as sparse");
}

}  // namespace jetshell
