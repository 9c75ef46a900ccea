#include "tools/scene/contact_at_start.h"

#include "core/format.h"
#include "tools/scene/near_pairs.h"

#include <algorithm>
#include <limits>
#include <map>
#include <utility>

namespace jetshell {

std::vector<std::string> contactAtStartWarnings(const Scene& scene, const std::vector<ActorBlock>& actors) {
  // The point-cloud actors' samples, stacked: their positions, actor and radius.
  std::vector<int> clouds;
  for (std::size_t a = 0; a < scene.shells.size() && a < actors.size(); ++a)
    if (scene.shells[a].colliderType == ColliderType::PointCloud) clouds.push_back(static_cast<int>(a));
  const auto self = [&](int a) {
    const PointCloudColliderParams& c = scene.shells[static_cast<std::size_t>(a)].pointCloudCollider;
    return c.selfContact && c.selfContactExclusionRatio < 1.0;  // otherwise no rest pair of it is within 2r
  };
  if (clouds.size() < 2 && !(clouds.size() == 1 && self(clouds[0]))) return {};
  int n = 0;
  double largest = 0.0;
  for (int a : clouds) {
    n += actors[static_cast<std::size_t>(a)].numVertices;
    largest = std::max(largest, scene.shells[static_cast<std::size_t>(a)].pointCloudCollider.radius);
  }
  Positions points(n, 3);
  std::vector<int> actorOf(static_cast<std::size_t>(n));
  std::vector<double> radius(static_cast<std::size_t>(n));
  int next = 0;
  for (int a : clouds) {
    const ActorBlock& b = actors[static_cast<std::size_t>(a)];
    points.middleRows(next, b.numVertices) = b.mesh.V;
    for (int k = 0; k < b.numVertices; ++k, ++next) {
      actorOf[static_cast<std::size_t>(next)] = a;
      radius[static_cast<std::size_t>(next)] = scene.shells[static_cast<std::size_t>(a)].pointCloudCollider.radius;
    }
  }
  // Pairs that interact as the contact term decides (other actors; one actor's beyond its exclusion distance),
  // nearer than their radii's sum, tallied by pair of actors (nothing is kept per pair).
  struct Tally {
    long long pairs = 0;
    double nearest = std::numeric_limits<double>::infinity(), reach = 0.0;
  };
  std::map<std::pair<int, int>, Tally> byActors;
  const auto tally = [&](int i, int j) {
    const int a = actorOf[static_cast<std::size_t>(i)], b = actorOf[static_cast<std::size_t>(j)];
    const double d = (points.row(i) - points.row(j)).norm();
    const double reach = radius[static_cast<std::size_t>(i)] + radius[static_cast<std::size_t>(j)];
    if (!(d < reach)) return true;
    if (a == b) {
      const PointCloudColliderParams& c = scene.shells[static_cast<std::size_t>(a)].pointCloudCollider;
      if (!(c.selfContact && d >= c.selfContactExclusionRatio * 2.0 * c.radius)) return true;
    }
    Tally& t = byActors[{std::min(a, b), std::max(a, b)}];
    ++t.pairs;
    if (d < t.nearest) {
      t.nearest = d;
      t.reach = reach;
    }
    return true;
  };
  const bool complete = visitNearPairs(points, 2.0 * largest, tally, kContactAtStartVisits);
  std::vector<std::string> warnings;
  constexpr std::size_t kMostWarnings = 20;
  const std::string atLeast = complete ? "" : "at least ";
  for (const auto& [actorPair, t] : byActors) {
    if (warnings.size() == kMostWarnings) {
      warnings.push_back("and " + std::to_string(byActors.size() - kMostWarnings) + " more actors or pairs of actors that start in contact");
      break;
    }
    const std::string& a = scene.shells[static_cast<std::size_t>(actorPair.first)].name;
    const std::string& b = scene.shells[static_cast<std::size_t>(actorPair.second)].name;
    const std::string who = actorPair.first == actorPair.second
                                ? "shell actor '" + a + "' starts in contact with itself"
                                : "shell actors '" + a + "' and '" + b + "' start in contact";
    warnings.push_back(who + ": " + atLeast + std::to_string(t.pairs) +
                       " pairs of point-cloud samples lie nearer than their radii's sum, the nearest " +
                       formatNumber("%.3g", t.nearest) + " m apart against " + formatNumber("%.3g", t.reach) +
                       " m; the penalty pushes them apart in the first steps (start the samples at least " +
                       formatNumber("%.3g", t.reach) + " m apart" +
                       (actorPair.first == actorPair.second ? ", or a selfContactExclusionRatio of at least 1)"
                                                            : ", or take smaller radii)"));
  }
  return warnings;
}

}  // namespace jetshell
