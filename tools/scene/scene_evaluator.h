// A scene's choice of evaluator for the membrane and bending energies (SCENES.md, "solver.evaluator"): the
// hand-chained passes (the default, faster today) or the stage framework (core/stage_graph.h), where no chain rule
// is written by hand. Both evaluate the same energies to round-off (tests/energies/shell/staged_vs_nested_test.cpp).
//
// Inputs: the validated scene and the system built from it. Output: every membrane and bending term of the
// system (elastic and stiffness damping) on the chosen evaluator. Call it before the edge rules are applied.
#pragma once

#include "solvers/shell_system.h"
#include "tools/scene/scene.h"

namespace jetshell {

void selectSceneEvaluator(const Scene& scene, ShellSystem& system);

}  // namespace jetshell
