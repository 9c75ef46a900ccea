// Contact samples too sparse for what they must catch, found from the reference meshes before anything runs:
//   - point clouds: samples (the vertices, spheres of radius r) a mean edge L apart leave a gap in the middle of
//     a face, about L/√3 from its corners; a sample of another layer (or of a far part of the same one) of
//     radius r' fits through it untouched when L/√3 > r + r';
//   - volume actors: a solid whose thinnest half-width w is below the gap between a shell's contact samples
//     (about L/√3 for vertices or face centroids, half that for three points a face) minus the pair's activation
//     distance ε fits between them unfelt: a rod under a coarse cloth pokes through it.
// Planes are not judged (no thin part); an SDF grid by a bound on its thinnest part that the scene reader takes
// from its samples (sdfGridThinnestHalfWidth: its shallowest ridge, the middle of a plate or the axis of a rod),
// which errs towards the wide, so a sampled rod or a thin fin on a thick block is named and a coarse grid is not
// for being coarse. Input: the scene and its resolved model (each actor's own mesh). Output: one warning per
// actor or pair, naming both and the size that would close the gap; at most 20, then one line counting the rest
// (a scene may hold 100,000 pairs). Warnings only: the scene runs as written.
#pragma once

#include "tools/scene/scene.h"
#include "tools/scene/scene_model.h"

#include <string>
#include <vector>

namespace jetshell {

std::vector<std::string> contactCoverageWarnings(const Scene& scene, const std::vector<ActorBlock>& actors);

}  // namespace jetshell
