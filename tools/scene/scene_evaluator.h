// A scene's choice of evaluator for the membrane energy (SCENES.md, "solver.evaluator"): one composed stage per
// face (perFace, the default) or the membrane's stage graph (staged, core/stage_graph.h). The bending term has one
// evaluator, its stage graph. Both membrane evaluators give the same energy to round-off
// (tests/energies/shell/staged_vs_nested_test.cpp), and neither writes a chain rule by hand.
//
// Inputs: the validated scene and the system built from it. Output: every membrane term of the system (elastic
// and stiffness damping) on the chosen evaluator.
#pragma once

#include "solvers/shell_system.h"
#include "tools/scene/scene.h"

namespace jetshell {

void selectSceneEvaluator(const Scene& scene, ShellSystem& system);

}  // namespace jetshell
