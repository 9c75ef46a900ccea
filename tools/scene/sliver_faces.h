// Sliver faces: triangles whose height (twice the area over the longest edge) is below a thousandth of that edge.
// The mesh reader refuses only faces degenerate to round-off (height at most 1e-12 of the edge); between the two,
// a mesh runs, but Newton slows down on it or stalls in its line search. Measured (a 1 m strip hanging from its
// top edge, 20 × 20 quads, 120 steps at 60 Hz): 0.5 mm wide (faces of height 5e-4 of their edge) it took 21 s
// against 0.9 s for the same strip one quad across (faces of 1e-2), and 0.2 mm wide (2e-4) it stalled after 5
// steps with "line_search_failure (no sufficient decrease ...)". CAD exports and narrow generated grids make them.
//
// Input: the scene and its resolved actors. Output: one warning per shell actor with such faces, with the count
// and the thinnest; at most 20, then one line counting the rest. Warnings only: the scene runs as written.
#pragma once

#include "tools/scene/scene.h"
#include "tools/scene/scene_model.h"

#include <string>
#include <vector>

namespace jetshell {

/// A face is a sliver when its height is below this fraction of its longest edge.
constexpr double kSliverHeightRatio = 1e-3;

std::vector<std::string> sliverFaceWarnings(const Scene& scene, const std::vector<ActorBlock>& actors);

}  // namespace jetshell
