// Layers that start in contact: point-cloud samples (energies/contact/point_cloud_contact.h) that interact and lie
// nearer at t = 0 than the sum of their radii. The penalty then holds energy before anything moves and pushes them
// apart in the first steps: two garments put on one another interpenetrating, a cloth placed inside another, or a
// self-contact whose exclusion ratio below 1 lets rest neighbours within 2r push on each other.
//
// Input: the scene and its resolved actors (their rest positions in world coordinates, which are the positions
// at t = 0). Output: one warning per pair of actors (or per actor, for its self-contact), with the number of
// pairs and the nearest, at most 20, then one line counting the rest. Warnings only: the scene runs as written.
// The search is the reader's bounded one (tools/scene/near_pairs.h).
#pragma once

#include "tools/scene/scene.h"
#include "tools/scene/scene_model.h"

#include <string>
#include <vector>

namespace jetshell {

/// Points visited a sample, in all, before the search stops (a sample sees about 27 cells of 2r_max, each with
/// a few samples of each layer: about 200 in a garment with r near its edge length).
constexpr long long kContactAtStartVisits = 1024;

std::vector<std::string> contactAtStartWarnings(const Scene& scene, const std::vector<ActorBlock>& actors);

}  // namespace jetshell
