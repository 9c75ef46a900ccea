// A scene's boundary-edge rules applied to its shell system (SCENES.md "edgeRules", VALIDATION.md "Boundary
// rules"): the clamp rule is the bending term's own edge rule (energies/shell/edge_rules.h) on the edges whose two
// ends some actor clamps (`clampRotation`); the moment-free free edge and symmetry planes are a correction term
// on the faces they change (validation/boundary_rule_term.h, term "boundary_rules", whose α, β are
// differentiable parameters like the bending term's).
//
// Inputs: the validated scene, the problem built from it (tools/scene/scene_problem.h) and the system built from
// that problem. Output: the system's bending term ruled, the correction term (if any) added to its objective.
#pragma once

#include "solvers/shell_system.h"
#include "tools/scene/scene.h"

#include <vector>

namespace jetshell {

/// The vertices some actor of the problem clamps (size N), or empty when none does.
std::vector<char> clampedVerticesOf(const ShellProblem& problem);

/// Applies the scene's edge rules to the system (nothing when it has no bending term).
void addSceneEdgeRules(const Scene& scene, const ShellProblem& problem, ShellSystem& system);

}  // namespace jetshell
