// Shells that start inside a solid: shell vertices whose signed distance to a volume actor (placed where it is at
// t = 0, or λ = 0) is negative. The contact penalty then starts with them deep in the solid and pushes them out in
// the first steps or load levels, with forces no step was sized for: a plate modelled through a ball, a cloth
// below its floor, a garment placed into a body. A static path usually fails at its first increment, a dynamic run
// starts with a jolt.
//
// Input: the scene and its resolved actors (rest positions in world coordinates, the positions at t = 0). Output:
// one warning per pair of shell and volume actor, with the count and the deepest vertex; at most 20, then one line
// counting the rest. A vertex on the surface within round-off (1e-9 of the mean edge) is not inside. Every vertex
// is asked of every volume actor once: the scene bounds that product (InputLimits::maxVolumeActorVertices).
// Warnings only: the scene runs as written.
#pragma once

#include "tools/scene/scene.h"
#include "tools/scene/scene_model.h"

#include <string>
#include <vector>

namespace jetshell {

std::vector<std::string> insideSolidWarnings(const Scene& scene, const std::vector<ActorBlock>& actors);

}  // namespace jetshell
