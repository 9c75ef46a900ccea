// A scene's boundary-edge rules applied to its shell system (SCENES.md "edgeRules", VALIDATION.md "Boundary
// rules"): every rule is the bending term's own edge rule (energies/shell/edge_rules.h), set on each actor's
// bending term by energies/shell/boundary_rules.h: the free rule on free edges, symmetry_plane on edges lying on
// a symmetry plane, the clamp rule on the edges whose two ends some actor clamps (`clampRotation`), the page's
// free rule on the edges a moment load turns; the bending stiffness damping takes the same rules.
//
// Inputs: the validated scene, the problem built from it (tools/scene/scene_problem.h) and the system built from
// that problem. Output: the system's bending terms ruled.
#pragma once

#include "solvers/shell_system.h"
#include "tools/scene/scene.h"

#include <vector>

namespace jetshell {

/// The vertices some actor of the problem clamps (size N), or empty when none does.
std::vector<char> clampedVerticesOf(const ShellProblem& problem);

/// Applies the scene's edge rules to every bending term of the system (nothing when it has none).
void addSceneEdgeRules(const Scene& scene, const ShellProblem& problem, ShellSystem& system);

}  // namespace jetshell
